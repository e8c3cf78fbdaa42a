#include "isf_test_util.h"

#include <epoxy/gl.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <memory>

#include "render/render.h"
#include "scene/scene.h"

namespace fs = std::filesystem;

namespace sdfvj::isftest {

namespace {
std::unique_ptr<HeadlessContext> ctx;
}  // namespace

void RequireGl() {
    static std::string error;
    if (!ctx && error.empty()) {
        auto c = std::make_unique<HeadlessContext>();
        if (c->Create(&error)) ctx = std::move(c);
    }
    if (!ctx) FAIL("no headless GL: " << error);
}

HeadlessContext& MainContext() {
    RequireGl();
    return *ctx;
}

unsigned MakeTexture(int w, int h, const std::function<std::array<uint8_t, 4>(int x, int y)>& f) {
    std::vector<uint8_t> px((size_t)w * h * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const auto c = f(x, y);
            for (int k = 0; k < 4; ++k) px[((size_t)(h - 1 - y) * w + x) * 4 + k] = c[k];   // GL: bottom row first
        }
    unsigned t = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, 1, GL_RGBA8, w, h);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(t, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
    return t;
}

void DeleteTexture(unsigned t) { glDeleteTextures(1, &t); }

Img ReadBack(unsigned texture, int w, int h) { return Img{w, h, ReadTextureRgba(texture, w, h)}; }

void LoadOrFail(IsfEffect& e, const std::string& path) {
    std::string error;
    if (!e.Load(path, &error)) FAIL(error);
}

std::string TestFile(const std::string& name) { return std::string(SDFVJ_ISF_TEST_FILES) + "/" + name; }
std::string ShippedEffect(const std::string& name) { return DataRoot() + "/shaders/isf/" + name + ".fs"; }

void Save(const std::string& name, const Img& img) {
    fs::create_directories(SDFVJ_TEST_OUTPUT_DIR);
    std::string error;
    WritePng(std::string(SDFVJ_TEST_OUTPUT_DIR) + "/" + name + ".png", img.w, img.h, img.px, &error);
}

std::string TempDir() {
    const fs::path d = fs::temp_directory_path() / ("sdfvj_isf_test_" + std::to_string(getpid()));
    fs::create_directories(d);
    return d.string();
}

}  // namespace sdfvj::isftest
