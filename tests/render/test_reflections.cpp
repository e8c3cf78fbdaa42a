// `direct_reflections` (render.glsl BOUNCE_LIGHT 2, BOUNCE_STEPS 48): the surface a reflection
// lands on is lit by the light directly, without its shadow ray or AO, and the reflected ray
// marches at most 48 steps; the primary surfaces keep everything. On the H200 it takes 17-24 % off
// the 7680x4320 show of mandelbulb and the fields (docs/performance.md, session 13).
#include <catch2/catch.hpp>

#include "gl_fixture.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

// An effect list that must parse, and that DescribeEffects names back as written.
EffectSet EffectsNamedBack(const std::string& list) {
    EffectSet e;
    std::string error;
    const bool parsed = ParseEffectList(list, &e, &error);
    INFO(list << ": " << error);
    REQUIRE(parsed);
    CHECK(DescribeEffects(e) == list);
    return e;
}

}  // namespace

TEST_CASE("direct_reflections: the effect list names it, and it is its own variant", "[reflections]") {
    EffectSet e = EffectsNamedBack("pbr,reflections=1,direct_reflections");
    std::string error;
    CHECK(e.directReflections);
    EffectSet full = e;
    full.directReflections = false;
    CHECK(full != e);   // another program, compiled and cached as a variant
    REQUIRE(ParseEffectList("-direct_reflections", &e, &error));
    CHECK_FALSE(e.directReflections);
    CHECK(ShowDirectReflectionsLightingTest().effects.directReflections);
    CHECK(ShowDirectReflectionsLightingTest().effects.reflections == 1);
}

// Measured at 160x90 (fragment, llvmpipe): character 0.1 %, field150 0.9 %, mandelbulb 4.8 % of the
// pixels past 8/255 against the show's full reflections (the fractal's occluded folds, seen in
// its mirror-like reflections, come out brighter without AO there).
TEST_CASE("direct_reflections: reflections stay, lit directly, and frames without one do not change", "[reflections]") {
    constexpr int kW = 160, kH = 90;
    for (const auto& [scene, bound] : {std::pair<const char*, double>{"character", 0.01}, {"field150", 0.02}, {"mandelbulb", 0.08}}) {
        SECTION(scene) {
            const EffectSet show = ShowLightingTest().effects;
            const EffectSet direct = ShowDirectReflectionsLightingTest().effects;
            EffectSet flat = show, flatDirect = direct;
            flat.reflections = flatDirect.reflections = 0;
            const Image full = RenderScene(scene, show, RenderPath::Fragment, kW, kH);
            const Image cheap = RenderScene(scene, direct, RenderPath::Fragment, kW, kH);
            const Image none = RenderScene(scene, flat, RenderPath::Fragment, kW, kH);
            // Without a reflection the switch has nothing to change.
            CHECK(RenderScene(scene, flatDirect, RenderPath::Fragment, kW, kH).rgba == none.rgba);
            const ImageDiff toFull = CompareImages(cheap, full, 8), toNone = CompareImages(cheap, none, 8);
            INFO("direct against full reflections: mean " << toFull.meanAbs << ", " << toFull.fractionOver * 100
                 << " % past 8/255; against no reflection: mean " << toNone.meanAbs);
            CHECK(toFull.maxAbs > 0);                        // the switch reached the program
            CHECK(toFull.fractionOver <= bound);             // and moved few pixels far
            CHECK(toNone.meanAbs > 1.5 * toFull.meanAbs);    // nearer the full reflections than none
        }
    }
}

// BOUNCE_BOUND (render.glsl, 4 by default): a reflection's shadow ray and AO are skipped where no
// values of theirs could move the pixel's display colour by more than 4/255. The frame with
// the bound against a copy without it (BOUNCE_BOUND 0): no pixel further than the bound, 4/255,
// plus one for the rounding to 8 bits; some pixels do move (the bound reached the program and
// skipped); and frames without a reflection are the same bytes. A wrong bound (the shadow's
// spread taken without the mirror's weight, say) moves pixels by far more.
TEST_CASE("bounce bound: a reflection's shadow and AO are skipped only where they cannot move a pixel by 4/255", "[reflections]") {
    constexpr int kW = 160, kH = 90;
    const std::filesystem::path dir = std::filesystem::path(SDFVJ_TEST_OUTPUT_DIR) / "bounce_bound";
    std::filesystem::create_directories(dir);
    for (const char* scene : {"character", "field150", "mandelbulb"}) {
        SECTION(scene) {
            const std::filesystem::path file = dir / (std::string(scene) + "_unbound.glsl");
            REQUIRE(WriteSceneCopy(scene, "#define BOUNCE_BOUND 0", file));
            const EffectSet show = ShowLightingTest().effects;
            for (RenderPath path : {RenderPath::Fragment, RenderPath::Compute}) {
                const Image bound = RenderScene(scene, show, path, kW, kH);
                const Image unbound = RenderScene(file.string(), show, path, kW, kH);
                const ImageDiff d = CompareImages(bound, unbound, 0);
                INFO(RenderPathName(path) << ": " << d.fractionOver * 100 << " % of pixels moved, mean " << d.meanAbs
                                          << ", max " << d.maxAbs);
                CHECK(d.maxAbs <= 5);
                CHECK(d.fractionOver > 0.001);
            }
            EffectSet flat = show;
            flat.reflections = 0;
            CHECK(RenderScene(scene, flat, RenderPath::Fragment, kW, kH).rgba ==
                  RenderScene(file.string(), flat, RenderPath::Fragment, kW, kH).rgba);
        }
    }
}

// `quad_reflections` (quad_reflections.glsl QUAD_REFLECTIONS): the bounce traced once per 2x2 pixels through
// their centre, in a dispatch before the frame, each pixel weighting it by its own Fresnel term. A
// frame drawn 2x2 supersampled, shown averaged 2x2, reflects at the shown pixel's rate: it must
// show nearly what tracing every pixel's bounce shows (the reflection of a neighbouring surface
// only where the quad's centre sees another one), far nearer than no reflection at all.
TEST_CASE("quad_reflections: the bounce traced once per 2x2 pixels shows, averaged 2x2, what every pixel's own bounce shows", "[reflections]") {
    CHECK(EffectsNamedBack("pbr,reflections=1,quad_reflections").quadReflections);
    constexpr int kW = 160, kH = 90;
    for (const char* scene : {"character", "field150", "mandelbulb"}) {
        SECTION(scene) {
            const EffectSet show = ShowLightingTest().effects, quads = ShowQuadReflectionsLightingTest().effects;
            EffectSet flat = show;
            flat.reflections = 0;
            const Image every = Downsample2x2(RenderScene(scene, show, RenderPath::Compute, 2 * kW, 2 * kH));
            const Image shared = Downsample2x2(RenderScene(scene, quads, RenderPath::Compute, 2 * kW, 2 * kH));
            const Image none = Downsample2x2(RenderScene(scene, flat, RenderPath::Compute, 2 * kW, 2 * kH));
            const ImageDiff toEvery = CompareImages(shared, every, 8), noneToEvery = CompareImages(none, every, 8);
            INFO("shown pixels, against every pixel's own bounce: " << toEvery.fractionOver * 100 << " % past 8/255, mean "
                 << toEvery.meanAbs << ", max " << toEvery.maxAbs << "; no reflection: mean " << noneToEvery.meanAbs << ", "
                 << noneToEvery.fractionOver * 100 << " %");
            CHECK(toEvery.maxAbs > 0);                              // the quads' pass reached the frame
            CHECK(toEvery.meanAbs < 0.2 * noneToEvery.meanAbs);     // and it reflects what the pixels' own bounces do
            // measured (the quads beside asked first, the default): character 0.02 %, mandelbulb 0.09 %,
            // field150 0.49 %; its own quad alone (QUAD_REFLECTIONS_NEAR 0): 0.007 %, 0.04 %, 0.38 %; with the
            // centres' light lent too (QUAD_SHADE as shipped: 7, mandelbulb 1): 0.06 %, 0.19 %, 0.63 %
            CHECK(toEvery.fractionOver <= 0.008);
            // The fragment path has no pass before the frame: every pixel traces its own bounce.
            CHECK(RenderScene(scene, quads, RenderPath::Fragment, kW, kH).rgba == RenderScene(scene, show, RenderPath::Fragment, kW, kH).rgba);
        }
    }
    // An odd size (the last quads half outside) and strips (the quads' pass runs once, whole).
    const EffectSet quads = ShowQuadReflectionsLightingTest().effects;
    const Image whole = RenderScene("midi", quads, RenderPath::Compute, 97, 71);
    CHECK(CompareImages(whole, RenderScene("midi", quads, RenderPath::Compute, 97, 71, 1.0, {}, Quality{}, 5), 0).maxAbs == 0);
    const ImageDiff odd = CompareImages(whole, RenderScene("midi", ShowLightingTest().effects, RenderPath::Compute, 97, 71), 8);
    INFO("97x71 against every pixel's bounce: " << odd.fractionOver * 100 << " % past 8/255");
    CHECK(odd.fractionOver <= 0.03);
}

// QUAD_SHADE 7 (quad_reflections.glsl; the default, mandelbulb's header keeps 1): the
// quads' pass lends its centre's occlusion, its shadow ray's "lit" where every sample's penumbra term
// passed QUAD_SHADE_LIT (1.25), and a shadow blended from the four centres around a pixel where all
// four are on its surface and agree within QUAD_SHADE_SPREAD (0.1), to the frame pixels on the
// centres' surface, which then trace none of their own. Shown averaged 2x2, the frame must show
// nearly what every pixel's own shadow ray and AO show (QUAD_SHADE 0), and the lend must reach it.
// The spread matters: blending across a shadow's edge (QUAD_SHADE_SPREAD 2) moves more pixels.
TEST_CASE("quad_reflections: the centres' occlusion and shadows lent to the pixels on their surface show what their own show", "[reflections]") {
    const std::filesystem::path dir = std::filesystem::path(SDFVJ_TEST_OUTPUT_DIR) / "quad_shade";
    std::filesystem::create_directories(dir);
    const EffectSet quads = ShowQuadReflectionsLightingTest().effects;
    constexpr int kW = 160, kH = 90;
    auto shown = [&](const std::string& scene, const char* defines) {
        const std::filesystem::path file = dir / (scene + "_" + std::to_string(std::hash<std::string>{}(defines)) + ".glsl");
        REQUIRE(WriteSceneCopy(scene, defines, file));
        return Downsample2x2(RenderScene(file.string(), quads, RenderPath::Compute, 2 * kW, 2 * kH));
    };
    for (const char* scene : {"character", "field150", "mandelbulb"}) {
        SECTION(scene) {
            const Image own = shown(scene, "#define QUAD_SHADE 0");
            const Image lent = shown(scene, "#define QUAD_SHADE 7");
            const Image aoLent = shown(scene, "#define QUAD_SHADE 1");
            const Image noMargin = shown(scene, "#define QUAD_SHADE 7\n#define QUAD_SHADE_SPREAD 2.0f");
            const ImageDiff d = CompareImages(lent, own, 8), da = CompareImages(aoLent, own, 8), dm = CompareImages(noMargin, own, 8);
            INFO("lent, against every pixel's own: " << d.fractionOver * 100 << " % past 8/255, mean " << d.meanAbs << ", max "
                 << d.maxAbs << "; the occlusion alone: " << da.fractionOver * 100 << " %, mean " << da.meanAbs
                 << "; blended across edges: " << dm.fractionOver * 100 << " %, mean " << dm.meanAbs);
            CHECK(da.maxAbs > 0);                                  // the occlusion reached the frame
            CHECK(CompareImages(lent, aoLent, 0).maxAbs > 0);      // and the shadow rays' verdicts
            CHECK(d.fractionOver <= 0.003);
            CHECK(d.meanAbs < 0.15);   // measured: character 0.02, mandelbulb 0.08, field150 0.11 (0.04-0.17 % past 8/255)
            CHECK(dm.meanAbs > d.meanAbs);
        }
    }
}

// With no reflection bounce (the seed's full lighting, `bench --tests full_quad_shade`) the quads' pass
// runs for the light alone where the scene asks (QUAD_SHADE_ALONE 1), at one sample a pixel: what
// the pixels borrow stays within a stated tolerance of their own. As shipped (QUAD_SHADE_ALONE 0) the
// effect draws the same bytes as the frame without it (no pass).
TEST_CASE("quad_reflections: with no bounce the quads' pass lends its light alone where the scene asks and draws what every pixel's own draws", "[reflections]") {
    const std::filesystem::path dir = std::filesystem::path(SDFVJ_TEST_OUTPUT_DIR) / "quad_shade_full";
    std::filesystem::create_directories(dir);
    const EffectSet full = SeedLightingTests().front().effects, quads = FullQuadShadeLightingTest().effects;
    REQUIRE(full.reflections == 0);
    constexpr int kW = 320, kH = 180;
    for (const char* scene : {"character", "field150"}) {
        SECTION(scene) {
            const std::filesystem::path ownFile = dir / (std::string(scene) + "_own.glsl"), lentFile = dir / (std::string(scene) + "_lent.glsl");
            REQUIRE(WriteSceneCopy(scene, "#define QUAD_SHADE 0\n#define QUAD_SHADE_ALONE 1", ownFile));
            REQUIRE(WriteSceneCopy(scene, "#define QUAD_SHADE 7\n#define QUAD_SHADE_ALONE 1", lentFile));
            const Image own = RenderScene(ownFile.string(), full, RenderPath::Compute, kW, kH);
            CHECK(CompareImages(RenderScene(ownFile.string(), quads, RenderPath::Compute, kW, kH), own, 0).maxAbs == 0);
            CHECK(CompareImages(RenderScene(scene, quads, RenderPath::Compute, kW, kH), RenderScene(scene, full, RenderPath::Compute, kW, kH), 0).maxAbs == 0);
            const Image lent = RenderScene(lentFile.string(), quads, RenderPath::Compute, kW, kH);
            const ImageDiff d = CompareImages(lent, own, 8);
            INFO("lent at one sample a pixel, against every pixel's own: " << d.fractionOver * 100 << " % past 8/255, mean " << d.meanAbs
                 << ", max " << d.maxAbs);
            CHECK(d.maxAbs > 0);   // the pass ran and lent
            // measured on llvmpipe: character 0.14 % past 8/255, mean 0.05; field150 0.50 %, a sample a pixel
            // (no average over four samples, as in the show, to soften a borrowed penumbra's step)
            CHECK(d.fractionOver <= 0.008);
            CHECK(d.meanAbs < 0.3);
        }
    }
}

// QUAD_REFLECTIONS_DEFER 1 (quad_reflections.glsl; mandelbulb declares it): a pixel that no quad lends its
// bounce to is listed by the frame, and a dispatch of its own traces the listed bounces. The same
// trace as in the frame (QUAD_REFLECTIONS_DEFER 0, the default), carried over as the frame had it:
// the same bytes, with room in the list for every pixel, with the default room (an eighth of the
// pixels; at this size mandelbulb lists about a quarter, so the rest trace their own in the frame)
// with room for 16, and asked for more room than memory holds. The list has pixels in it (the path
// ran).
TEST_CASE("quad_reflections: the bounces left to a list of their own draw what the frame's own draw", "[reflections]") {
    const std::filesystem::path dir = std::filesystem::path(SDFVJ_TEST_OUTPUT_DIR) / "quad_defer";
    std::filesystem::create_directories(dir);
    const EffectSet quads = ShowQuadReflectionsLightingTest().effects;
    constexpr int kW = 192, kH = 108;
    for (const char* scene : {"mandelbulb", "field150"}) {
        SECTION(scene) {
            const std::filesystem::path inFrameFile = dir / (std::string(scene) + "_in_frame.glsl");
            const std::filesystem::path listedFile = dir / (std::string(scene) + "_listed.glsl");
            REQUIRE(WriteSceneCopy(scene, "#define QUAD_REFLECTIONS_DEFER 0", inFrameFile));
            REQUIRE(WriteSceneCopy(scene, "#define QUAD_REFLECTIONS_DEFER 1", listedFile));
            long long none = 0, shipped = 0;
            const Image inFrame = RenderScene(inFrameFile.string(), quads, RenderPath::Compute, kW, kH, 1.0, {}, Quality{}, 1, -1, &none);
            CHECK(none == 0);   // the copy without has no list
            // As shipped: mandelbulb lists (its header asks), field150 does not.
            const Image asShipped = RenderScene(scene, quads, RenderPath::Compute, kW, kH, 1.0, {}, Quality{}, 1, -1, &shipped);
            CHECK((shipped > 0) == (std::string(scene) == "mandelbulb"));
            CHECK(CompareImages(asShipped, inFrame, 0).maxAbs == 0);
            long long first = -1;
            // Room for every pixel, the default, 16, and more than any memory holds (the list then has
            // room for none: every bounce traced in the frame).
            for (long long room : {(long long)kW * kH, -1LL, 16LL, 1LL << 40}) {
                long long listed = 0;
                const Image img = RenderScene(listedFile.string(), quads, RenderPath::Compute, kW, kH, 1.0, {}, Quality{}, 1, room, &listed);
                const ImageDiff d = CompareImages(img, inFrame, 0);
                INFO("room " << room << ": " << listed << " of " << kW * kH << " pixels listed; against the frame's own: max "
                     << d.maxAbs << ", " << d.fractionOver * 100 << " % moved");
                CHECK(listed > 16);                              // some bounces went to the list
                CHECK(listed == (first < 0 ? listed : first));   // the same pixels asked, whatever the room
                first = listed;
                CHECK(d.maxAbs == 0);
            }
        }
    }
}
