#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include "render/render.h"

namespace sdfvj {

bool WritePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba, std::string* error) {
    if (!stbi_write_png(path.c_str(), width, height, 4, rgba.data(), width * 4)) {
        *error = "cannot write " + path;
        return false;
    }
    return true;
}

}  // namespace sdfvj
