// Helpers for the ISF tests: one headless context per process, textures from a function of the
// pixel, and read-back in image order (top row first, as PNGs are).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "isf/isf.h"
#include "render/render.h"

namespace sdfvj::isftest {

// FAILs the test when there is no GL 4.5 through EGL.
void RequireGl();
// The context RequireGl made current (for contexts that share objects with it).
HeadlessContext& MainContext();

struct Img {
    int w = 0, h = 0;
    std::vector<uint8_t> px;   // RGBA, top row first
    int At(int x, int y, int c) const { return px[((size_t)y * w + x) * 4 + c]; }
};

// An RGBA8 texture whose pixel (x, y) (y = 0 the top row) is f(x, y). Caller deletes it.
unsigned MakeTexture(int w, int h, const std::function<std::array<uint8_t, 4>(int x, int y)>& f);
void DeleteTexture(unsigned t);
Img ReadBack(unsigned texture, int w, int h);

// Loads a file or FAILs with its error.
void LoadOrFail(IsfEffect& e, const std::string& path);
// files/NAME and shaders/isf/NAME.fs
std::string TestFile(const std::string& name);
std::string ShippedEffect(const std::string& name);
// Writes build/test-images/isf/NAME.png (to look at).
void Save(const std::string& name, const Img& img);
// A temporary folder for files a test writes (IMPORTED images, edited shaders).
std::string TempDir();

}  // namespace sdfvj::isftest
