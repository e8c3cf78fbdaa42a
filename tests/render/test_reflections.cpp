// `direct_reflections` (render.glsl BOUNCE_LIGHT 2, BOUNCE_STEPS 48): the surface a reflection
// lands on is lit by the light directly, without its shadow ray or AO, and the reflected ray
// marches at most 48 steps; the primary surfaces keep everything. On the H200 it takes 17-24 % off
// the 7680x4320 show of mandelbulb and the fields (docs/performance.md, session 13).
#include <catch2/catch.hpp>

#include "gl_fixture.h"

using namespace sdfvj;
using namespace sdfvj::test;

TEST_CASE("direct_reflections: the effect list names it, and it is its own variant", "[reflections]") {
    EffectSet e;
    std::string error;
    REQUIRE(ParseEffectList("pbr,reflections=1,direct_reflections", &e, &error));
    CHECK(e.directReflections);
    CHECK(DescribeEffects(e) == "pbr,reflections=1,direct_reflections");
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
