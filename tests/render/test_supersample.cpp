// The `ssaa` effect (render/supersample.glsl): four samples a pixel on a rotated grid. Each is
// marched on its own; `ssaa_exact` shades each sample, `ssaa` shades once per surface the samples
// see (both miss, or the same albedo at nearly the same depth) and gives that colour to every
// sample of the surface. The ground truth of 4x supersampling is a frame twice as wide and tall,
// averaged 2x2 (another sample pattern: ordered, not rotated). Tolerances are stated against the
// one-sample frame's own error, so they hold on any renderer that anti-aliases at all.
#include <catch2/catch.hpp>

#include "gl_fixture.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

EffectSet Show(int supersample) {
    EffectSet e = ShowLightingTest().effects;
    e.supersample = supersample;
    return e;
}

}  // namespace

TEST_CASE("ssaa: the effect list names it, and it is its own variant", "[supersample]") {
    EffectSet e;
    std::string error;
    REQUIRE(ParseEffectList("soft_shadows,ssaa", &e, &error));
    CHECK(e.supersample == 1);
    CHECK(DescribeEffects(e) == "soft_shadows,ssaa");
    REQUIRE(ParseEffectList("ssaa_exact", &e, &error));
    CHECK(e.supersample == 2);
    REQUIRE(ParseEffectList("-ssaa_exact", &e, &error));
    CHECK(e.supersample == 0);
    CHECK_FALSE(ParseEffectList("ssaa8", &e, &error));
    CHECK(error.find("ssaa") != std::string::npos);
    EffectSet a = e, b = e;
    b.supersample = 1;
    CHECK(a != b);   // another program, compiled and cached as a variant
}

TEST_CASE("ssaa: four samples a pixel draw the supersampled frame, and shading shared per surface stays near it", "[supersample]") {
    constexpr int kW = 160, kH = 90;
    for (const std::string scene : {"character", "field150", "midi"}) {
        SECTION(scene) {
            const Image truth = Downsample2x2(RenderScene(scene, Show(0), RenderPath::Fragment, 2 * kW, 2 * kH));
            const Image one = RenderScene(scene, Show(0), RenderPath::Fragment, kW, kH);
            const Image exact = RenderScene(scene, Show(2), RenderPath::Fragment, kW, kH);
            const Image shared = RenderScene(scene, Show(1), RenderPath::Fragment, kW, kH);
            const ImageDiff oneErr = CompareImages(one, truth, 8), exactErr = CompareImages(exact, truth, 8);
            INFO("against 2x2 of a frame twice the size: one sample mean " << oneErr.meanAbs << " (over 8/255 "
                 << oneErr.fractionOver * 100 << "%), four samples each shaded " << exactErr.meanAbs << " ("
                 << exactErr.fractionOver * 100 << "%)");
            // Anti-aliased: the four samples land near the supersampled frame, the one sample does not.
            CHECK(exactErr.meanAbs < 0.6 * oneErr.meanAbs);
            CHECK(exactErr.fractionOver < 0.6 * oneErr.fractionOver);
            // The shared shading: closer to every sample shaded than one sample is, and no pixel far off.
            const ImageDiff sharedErr = CompareImages(shared, exact, 8), oneToExact = CompareImages(one, exact, 8);
            INFO("against each sample shaded: shared mean " << sharedErr.meanAbs << " (over 8/255 "
                 << sharedErr.fractionOver * 100 << "%, max " << sharedErr.maxAbs << "), one sample " << oneToExact.meanAbs
                 << " (" << oneToExact.fractionOver * 100 << "%)");
            CHECK(sharedErr.meanAbs < 0.3 * oneToExact.meanAbs);
            CHECK(sharedErr.fractionOver < 0.3 * oneToExact.fractionOver);
            // The compute path (its cone pre-pass widened to the samples' reach) draws what the fragment
            // path draws: its rays stop a step apart, which may flip a pixel between shared and
            // per-sample shading; one sample a pixel reads 0.06-0.13 % past 8/255 here, ssaa 0.19-0.59 %,
            // and 0.90 % on field150 with the pre-pass's cones not widened to the samples.
            const Image compute = RenderScene(scene, Show(1), RenderPath::Compute, kW, kH);
            const ImageDiff paths = CompareImages(compute, shared, 8);
            const ImageDiff plainPaths = CompareImages(RenderScene(scene, Show(0), RenderPath::Compute, kW, kH), one, 8);
            INFO("compute against fragment: over 8/255 " << paths.fractionOver * 100 << "%, max " << paths.maxAbs
                 << "; one sample a pixel: " << plainPaths.fractionOver * 100 << "%, max " << plainPaths.maxAbs);
            CHECK(paths.fractionOver <= 0.0075);
        }
    }
}

TEST_CASE("compute strips: a frame drawn in strips, a wait after each, is the one-dispatch frame to the byte") {
    // A render server draws a new program's first frame in strips (SDFVJ_SERVER_STRIPS) so the
    // show's frames are not queued behind it on a shared GPU: the picture must not change. Odd
    // sizes leave a last strip shorter than the others; character's work-groups are 16x16, midi's 8x8.
    for (const char* name : {"midi", "character"}) {
        for (int strips : {2, 5, 64}) {
            INFO(name << " in " << strips << " strips");
            const Image one = RenderScene(name, EffectSet{}, RenderPath::Compute, 97, 71, 1.3);
            const Image split = RenderScene(name, EffectSet{}, RenderPath::Compute, 97, 71, 1.3, {}, Quality{}, strips);
            const ImageDiff d = CompareImages(one, split, 0);
            CHECK(d.maxAbs == 0);
            CHECK(MeanLuma(split, 0.0, 0.0, 1.0, 1.0) > 5.0);   // drawn, not a cleared target
            CHECK(MeanLuma(split, 0.0, 0.0, 1.0, 0.1) > 5.0);   // the top rows too (the last strip; rows come top first)
        }
    }
}
