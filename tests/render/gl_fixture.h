// Shared helpers for GL tests: one headless EGL context per test process (Mesa llvmpipe in CI),
// rendering a scene variant to RGBA, and image comparison with a stated tolerance.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "render/render.h"

namespace sdfvj::test {

// The process-wide context; FAILs the test with the reason when no GL is available.
void RequireGl();
// The process-wide context RequireGl() made (null when there is none).
HeadlessContext* TestContext();

struct Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;   // top row first
};

// Renders one frame of a scene with an effect set on a path. FAILs on compile errors. `strips`:
// FrameRenderer::SetStrips (the compute path's frame in horizontal strips). `deferRoom`:
// FrameRenderer::SetQuadDeferRoom; where `deferred` is given, it gets LastQuadDeferred.
Image RenderScene(const std::string& scene, const EffectSet& effects, RenderPath path, int width, int height,
                  double time = 1.0, const std::vector<std::pair<std::string, float>>& params = {},
                  const Quality& quality = {}, int strips = 1, long long deferRoom = -1, long long* deferred = nullptr);

bool LoadPng(const std::string& path, Image* out);
bool SavePng(const std::string& path, const Image& img);

// How far two images are apart: the tolerance is stated in terms of these.
struct ImageDiff {
    double meanAbs = 0;         // mean |a-b| over all RGB channels, in 0..255 units
    int maxAbs = 0;             // largest channel difference
    double fractionOver = 0;    // fraction of pixels with any channel off by more than `threshold`
};
ImageDiff CompareImages(const Image& a, const Image& b, int threshold);

// Mean luminance of a rectangle (fractions of the image), 0..255.
double MeanLuma(const Image& img, double x0, double y0, double x1, double y1);

// Each 2x2 block's mean (accuracy::DownsampleRgba8x2): a frame drawn at twice the size, as shown.
Image Downsample2x2(const Image& big);

// A copy of a shipped scene at `file` with `defines` (lines) right after its header, where a scene
// declares its own switches. False when the scene is unknown or has no header.
bool WriteSceneCopy(const std::string& scene, const std::string& defines, const std::filesystem::path& file);

}  // namespace sdfvj::test
