// Image files for IMPORTED (stb_image, from Debian's libstb-dev) and texture read-back.
#define STB_IMAGE_STATIC   // tests link another stb_image; ours stays private to this file
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_HDR
#define STBI_NO_PIC
#define STBI_NO_PNM
#define STBI_NO_PSD
#define STBI_NO_GIF
#include <stb/stb_image.h>

#include <epoxy/gl.h>

#include <cstring>

#include "isf/isf.h"

namespace sdfvj {

bool LoadImageRgba(const std::string& path, int* w, int* h, std::vector<uint8_t>* rgba, std::string* error) {
    int n = 0;
    stbi_set_flip_vertically_on_load_thread(1);   // GL's first row is the bottom one
    unsigned char* pixels = stbi_load(path.c_str(), w, h, &n, 4);
    stbi_set_flip_vertically_on_load_thread(0);
    if (!pixels) {
        *error = path + ": cannot read the image (" + stbi_failure_reason() + "), expected a PNG, JPEG, BMP or TGA file";
        return false;
    }
    if (*w <= 0 || *h <= 0 || *w > 16384 || *h > 16384) {
        stbi_image_free(pixels);
        *error = path + ": the image is " + std::to_string(*w) + "x" + std::to_string(*h) + ", expected 1..16384 per side";
        return false;
    }
    rgba->assign(pixels, pixels + (size_t)*w * *h * 4);
    stbi_image_free(pixels);
    return true;
}

std::vector<uint8_t> ReadTextureRgba(unsigned texture, int w, int h) {
    std::vector<uint8_t> rgba((size_t)w * h * 4);
    if (!texture) return rgba;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, (GLsizei)rgba.size(), rgba.data());
    const size_t row = (size_t)w * 4;   // bottom-first -> top-first
    std::vector<uint8_t> tmp(row);
    for (int y = 0; y < h / 2; ++y) {
        uint8_t* a = rgba.data() + row * y;
        uint8_t* b = rgba.data() + row * (h - 1 - y);
        std::memcpy(tmp.data(), a, row);
        std::memcpy(a, b, row);
        std::memcpy(b, tmp.data(), row);
    }
    return rgba;
}

}  // namespace sdfvj
