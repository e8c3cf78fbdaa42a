#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "gl_fixture.h"

#include "accuracy/accuracy.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>

namespace sdfvj::test {

namespace {
std::unique_ptr<HeadlessContext> ctx;
std::string error;
}  // namespace

HeadlessContext* TestContext() { return ctx.get(); }

void RequireGl() {
    if (!ctx && error.empty()) {
        // Tests compile what they test: the on-disk program cache is off unless a test turns it
        // on (test_program_cache.cpp, with a cache folder of its own).
        setenv("SDFVJ_PROGRAM_CACHE", "0", 1);
        auto c = std::make_unique<HeadlessContext>();
        if (c->Create(&error)) ctx = std::move(c);
    }
    if (!ctx) FAIL("no headless GL: " << error);
}

Image RenderScene(const std::string& sceneName, const EffectSet& effects, RenderPath path, int width, int height,
                  double time, const std::vector<std::pair<std::string, float>>& params, const Quality& quality, int strips,
                  long long deferRoom, long long* deferred) {
    RequireGl();
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene(sceneName, &scene, &error));
    ShaderSource src;
    INFO(error);
    REQUIRE(AssembleProgram(scene, VariantKey{scene.path, effects, path}, &src, &error));
    Program prog;
    if (!prog.Build(src, path, &error)) FAIL(error);
    FrameRenderer fr;
    REQUIRE(fr.Resize(width, height, &error));
    FrameInputs in;
    in.time = time;
    in.quality = quality;
    for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
    for (auto& [n, v] : in.params)
        for (const auto& [pn, pv] : params)
            if (n == pn) v = pv;
    fr.SetStrips(strips);
    fr.SetQuadDeferRoom(deferRoom);
    fr.Draw(prog, scene, in);
    if (deferred) *deferred = fr.LastQuadDeferred();
    return Image{width, height, fr.ReadPixels()};
}

bool LoadPng(const std::string& path, Image* out) {
    int w, h, n;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 4);
    if (!data) return false;
    out->width = w;
    out->height = h;
    out->rgba.assign(data, data + (size_t)w * h * 4);
    stbi_image_free(data);
    return true;
}

bool SavePng(const std::string& path, const Image& img) {
    std::string err;
    return WritePng(path, img.width, img.height, img.rgba, &err);
}

ImageDiff CompareImages(const Image& a, const Image& b, int threshold) {
    ImageDiff d;
    if (a.width != b.width || a.height != b.height) {
        d.meanAbs = 255;
        d.maxAbs = 255;
        d.fractionOver = 1;
        return d;
    }
    double sum = 0;
    size_t over = 0;
    const size_t pixels = (size_t)a.width * a.height;
    for (size_t i = 0; i < pixels; ++i) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
            int diff = std::abs((int)a.rgba[i * 4 + c] - (int)b.rgba[i * 4 + c]);
            sum += diff;
            worst = std::max(worst, diff);
        }
        d.maxAbs = std::max(d.maxAbs, worst);
        if (worst > threshold) ++over;
    }
    d.meanAbs = sum / (pixels * 3.0);
    d.fractionOver = (double)over / pixels;
    return d;
}

double MeanLuma(const Image& img, double x0, double y0, double x1, double y1) {
    double sum = 0;
    int n = 0;
    for (int y = (int)(y0 * img.height); y < (int)(y1 * img.height); ++y)
        for (int x = (int)(x0 * img.width); x < (int)(x1 * img.width); ++x) {
            const uint8_t* p = &img.rgba[((size_t)y * img.width + x) * 4];
            sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            ++n;
        }
    return n ? sum / n : 0.0;
}

Image Downsample2x2(const Image& big) {
    return Image{big.width / 2, big.height / 2, accuracy::DownsampleRgba8x2(big.rgba, big.width, big.height)};
}

bool WriteSceneCopy(const std::string& scene, const std::string& defines, const std::filesystem::path& file) {
    SceneInfo info;
    std::string error;
    if (!FindScene(scene, &info, &error)) return false;
    std::ifstream in(info.path);
    std::stringstream text;
    text << in.rdbuf();
    const std::string original = text.str();
    const size_t header = original.find("}*/");
    if (header == std::string::npos) return false;
    std::ofstream(file) << original.substr(0, header + 3) << "\n" << defines << original.substr(header + 3);
    return true;
}

}  // namespace sdfvj::test
