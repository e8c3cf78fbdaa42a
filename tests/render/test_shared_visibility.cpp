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

TEST_CASE("shared visibility: every scene draws what every pixel's own shadows and AO draw", "[visibility]") {
    const fs::path dir = fs::path(SDFVJ_TEST_OUTPUT_DIR) / "visibility";
    fs::create_directories(dir);
    for (const std::string& scene : ListScenes()) {
        SECTION(scene) {
            SceneInfo info;
            std::string error;
            REQUIRE(FindScene(scene, &info, &error));
            EffectSet full = SeedLightingTests()[0].effects;   // soft shadows, AO, specular
            full.normals = info.effects.normals;
            Quality own, on;
            own.shareVisibility = 0;
            on.shareVisibility = 1;
            Image shared = RenderScene(scene, full, RenderPath::Compute, 320, 180, 1.0, {}, on);
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
