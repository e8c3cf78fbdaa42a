// The `ssaa` effect (render/supersample.glsl): four samples a pixel on a rotated grid. Each is
// marched on its own; `ssaa_exact` shades each sample, `ssaa` shades once per surface the samples
// see (both miss, or the same albedo at nearly the same depth) and gives that colour to every
// sample of the surface. The ground truth of 4x supersampling is a frame twice as wide and tall,
// averaged 2x2 (another sample pattern: ordered, not rotated). Tolerances are stated against the
// one-sample frame's own error, so they hold on any renderer that anti-aliases at all.
#include <catch2/catch.hpp>

#include "accuracy/accuracy.h"
#include "gl_fixture.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

Image Downsample2x2(const Image& big) {
    return Image{big.width / 2, big.height / 2, accuracy::DownsampleRgba8x2(big.rgba, big.width, big.height)};
}

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

namespace {

// The largest channel spread of the 2x2 quad at (x, y).
int QuadSpread(const Image& img, int x, int y) {
    int spread = 0;
    for (int c = 0; c < 3; ++c) {
        int lo = 255, hi = 0;
        for (int s = 0; s < 4; ++s) {
            int v = img.rgba[((y + s / 2) * img.width + x + s % 2) * 4 + c];
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
        spread = std::max(spread, hi - lo);
    }
    return spread;
}

// The share of 2x2 quads that are one colour up to the dither (2/255) in `shared` but not in `each`.
double QuadsMadeOneColour(const Image& shared, const Image& each) {
    int quads = 0, made = 0;
    for (int y = 0; y + 1 < shared.height; y += 2)
        for (int x = 0; x + 1 < shared.width; x += 2, ++quads)
            if (QuadSpread(shared, x, y) <= 2 && QuadSpread(each, x, y) > 2) ++made;
    return quads ? double(made) / quads : 0.0;
}

}  // namespace

TEST_CASE("ssaa_quads: a frame twice the size whose quads share their shading, averaged 2x2, draws what shading every pixel draws", "[supersample]") {
    EffectSet e;
    std::string error;
    REQUIRE(ParseEffectList("pbr,ssaa_quads", &e, &error));
    CHECK(e.supersample == 3);
    CHECK(DescribeEffects(e) == "pbr,ssaa_quads");
    constexpr int kW = 160, kH = 90;
    for (const std::string scene : {"character", "field150", "midi"}) {
        SECTION(scene) {
            const Image plainBig = RenderScene(scene, Show(0), RenderPath::Compute, 2 * kW, 2 * kH);
            const Image quadsBig = RenderScene(scene, Show(3), RenderPath::Compute, 2 * kW, 2 * kH);
            const Image plain = Downsample2x2(plainBig), quads = Downsample2x2(quadsBig);
            const Image one = RenderScene(scene, Show(0), RenderPath::Compute, kW, kH);
            const ImageDiff quadsErr = CompareImages(quads, plain, 8), oneErr = CompareImages(one, plain, 8);
            const double made = QuadsMadeOneColour(quadsBig, plainBig), unmade = QuadsMadeOneColour(plainBig, quadsBig);
            INFO("against every pixel shaded, 2x2 averaged: quads shared mean " << quadsErr.meanAbs << " (over 8/255 "
                 << quadsErr.fractionOver * 100 << "%, max " << quadsErr.maxAbs << "), one sample a shown pixel "
                 << oneErr.meanAbs << " (" << oneErr.fractionOver * 100 << "%); quads made one colour by the sharing: "
                 << made * 100 << "%, the other way " << unmade * 100 << "%");
            // The quads did share: quads whose pixels differ when each is shaded are one colour.
            CHECK(made > 0.02);
            CHECK(unmade < 0.002);
            // And the shown image stays near the one shaded per pixel: far nearer than one sample a pixel.
            CHECK(quadsErr.meanAbs < 0.3 * oneErr.meanAbs);
            CHECK(quadsErr.fractionOver < 0.3 * oneErr.fractionOver);
            // The fragment path has no work-group to share with: it shades every pixel.
            const ImageDiff fragment = CompareImages(RenderScene(scene, Show(3), RenderPath::Fragment, 2 * kW, 2 * kH),
                                                     RenderScene(scene, Show(0), RenderPath::Fragment, 2 * kW, 2 * kH), 0);
            CHECK(fragment.maxAbs == 0);
        }
    }
    // Odd sizes (a quad cut by the edge shades its pixels each) and strips (each strip whole work-groups).
    const Image whole = RenderScene("midi", Show(3), RenderPath::Compute, 97, 71);
    const Image strips = RenderScene("midi", Show(3), RenderPath::Compute, 97, 71, 1.0, {}, Quality{}, 5);
    CHECK(CompareImages(whole, strips, 0).maxAbs == 0);
    const ImageDiff odd = CompareImages(whole, RenderScene("midi", Show(0), RenderPath::Compute, 97, 71), 8);
    INFO("odd size: over 8/255 " << odd.fractionOver * 100 << "%");
    CHECK(odd.fractionOver < 0.02);
    CHECK(MeanLuma(whole, 0.0, 0.0, 1.0, 0.1) > 5.0);
    CHECK(MeanLuma(whole, 0.9, 0.0, 1.0, 1.0) > 5.0);
}
