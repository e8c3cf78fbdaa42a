// Shared visibility (main_comp.glsl, Quality::shareVisibility, on by default on the compute path):
// shadows and AO traced from one pixel of each 2x2 quad and interpolated by the quad's other pixels
// where they lie on the representative's surface; silhouettes and creases trace their own. The
// tolerance is stated against what the effects themselves change: the shared frame must stay far
// closer to every pixel's own shadows and AO than a frame without them is.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "gl_fixture.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {
// Compiles shared visibility into compute programs for the scope (a context on llvmpipe leaves it
// out, see the last test), then puts back what the context chose.
struct CompiledIn {
    bool was;
    CompiledIn() {
        RequireGl();   // the context sets it first
        was = ComputeSharedVisibility();
        SetComputeSharedVisibility(true);
    }
    ~CompiledIn() { SetComputeSharedVisibility(was); }
};
}  // namespace

TEST_CASE("shared visibility: every scene draws what every pixel's own shadows and AO draw", "[visibility]") {
    const fs::path dir = fs::path(SDFVJ_TEST_OUTPUT_DIR) / "visibility";
    fs::create_directories(dir);
    CompiledIn compiled;
    for (const std::string& scene : ListScenes()) {
        SECTION(scene) {
            SceneInfo info;
            std::string error;
            REQUIRE(FindScene(scene, &info, &error));
            EffectSet full = SeedLightingTests()[0].effects;   // soft shadows, AO, specular
            full.normals = info.effects.normals;
            Quality own;
            own.shareVisibility = false;
            Image shared = RenderScene(scene, full, RenderPath::Compute, 320, 180);
            Image each = RenderScene(scene, full, RenderPath::Compute, 320, 180, 1.0, {}, own);
            EffectSet bare = full;
            bare.shadows = 0;
            bare.ao = false;
            Image none = RenderScene(scene, bare, RenderPath::Compute, 320, 180, 1.0, {}, own);
            SavePng((dir / (scene + "_shared.png")).string(), shared);
            SavePng((dir / (scene + "_own.png")).string(), each);
            Image diff = shared;   // |shared - own| x 8, to look at
            for (size_t i = 0; i < diff.rgba.size(); ++i)
                diff.rgba[i] = i % 4 == 3 ? 255 : (uint8_t)std::min(255, 8 * std::abs((int)shared.rgba[i] - (int)each.rgba[i]));
            SavePng((dir / (scene + "_diff.png")).string(), diff);
            ImageDiff d = CompareImages(shared, each, 8);
            ImageDiff e = CompareImages(none, each, 8);
            INFO("shared against own: " << d.fractionOver * 100 << " % of pixels past 8/255, mean " << d.meanAbs
                                        << ", max " << d.maxAbs << "; without shadows and AO: " << e.fractionOver * 100
                                        << " %, mean " << e.meanAbs);
            REQUIRE(e.fractionOver > 0.02);   // the effects show in this frame
            CHECK(d.fractionOver <= 0.05 * e.fractionOver);
            CHECK(d.meanAbs <= 0.05 * e.meanAbs);
        }
    }
}

// Where it would cost: llvmpipe runs every invocation of a compute program that has barriers as a
// coroutine, 70 % slower at 640x360 even with the branch not taken, so a context there compiles
// the path out (SHARED_VISIBILITY 0), and a compute program without it draws what a pixel that
// traces its own draws, whatever Quality::shareVisibility says.
TEST_CASE("shared visibility: compiled out on a software renderer", "[visibility]") {
    RequireGl();
    const std::vector<std::string> defines = VariantDefines(EffectSet{}, RenderPath::Compute);
    const bool out = std::find(defines.begin(), defines.end(), "SHARED_VISIBILITY 0") != defines.end();
    const char* force = std::getenv("SDFVJ_SHARED_VISIBILITY");
    if (force) return;   // forced either way: nothing to check
    CHECK(out == IsSoftwareRenderer());
    CHECK(ComputeSharedVisibility() == !IsSoftwareRenderer());
    const std::vector<std::string> fragment = VariantDefines(EffectSet{}, RenderPath::Fragment);
    CHECK(std::find(fragment.begin(), fragment.end(), "SHARED_VISIBILITY 0") == fragment.end());
    if (!out) return;
    EffectSet full = SeedLightingTests()[0].effects;
    Quality own;
    own.shareVisibility = false;
    Image a = RenderScene("character", full, RenderPath::Compute, 64, 48);
    Image b = RenderScene("character", full, RenderPath::Compute, 64, 48, 1.0, {}, own);
    CHECK(a.rgba == b.rgba);
}
