// effect_sets.cpp - named sets of effects: the seed thesis's four lighting tests, issue 13's show
// lighting, and what an effect pad reaches from a variant (scene.h).
#include "scene/scene.h"

namespace sdfvj {

std::vector<LightingTest> SeedLightingTests() {
    EffectSet full, shadowsAo, shadows, none;
    full.shadows = shadowsAo.shadows = shadows.shadows = 2;
    full.ao = shadowsAo.ao = true;
    full.specular = true;
    return {{"full", full}, {"shadows_ao", shadowsAo}, {"shadows", shadows}, {"none", none}};
}

std::vector<EffectSet> OneEffectToggles(const EffectSet& e) {
    std::vector<EffectSet> out;
    auto add = [&](auto change) {
        EffectSet t = e;
        change(t);
        out.push_back(t);
    };
    add([](EffectSet& t) { t.shadows = t.shadows ? 0 : 2; });
    add([](EffectSet& t) { t.ao = !t.ao; });
    add([](EffectSet& t) { t.specular = !t.specular; });
    add([](EffectSet& t) { t.fog = !t.fog; });
    add([](EffectSet& t) { t.pbr = !t.pbr; });
    add([](EffectSet& t) { t.reflections = t.reflections ? 0 : 1; });
    return out;
}

LightingTest ShowLightingTest() {
    EffectSet show;
    show.shadows = 2;
    show.ao = show.specular = show.pbr = true;
    show.reflections = 1;
    return {"show", show};
}

LightingTest ShowSupersampledLightingTest(bool exact) {
    LightingTest t = ShowLightingTest();
    t.effects.supersample = exact ? 2 : 1;
    t.name = exact ? "show_ssaa_exact" : "show_ssaa";
    return t;
}

std::vector<LightingTest> FramePartTests() {
    EffectSet march, normals;
    march.debugView = 2;
    normals.debugView = 3;
    return {{"march", march}, {"normals", normals}};
}

LightingTest ShowQuadReflectionsLightingTest() {
    LightingTest t = ShowLightingTest();
    t.effects.quadReflections = true;
    t.name = "show_quad_reflections";
    return t;
}

LightingTest FullQuadShadeLightingTest() {
    LightingTest t = SeedLightingTests().front();
    t.effects.quadReflections = true;
    t.name = "full_quad_shade";
    return t;
}

LightingTest ShowDirectReflectionsLightingTest() {
    LightingTest t = ShowLightingTest();
    t.effects.directReflections = true;
    t.name = "show_direct";
    return t;
}

}  // namespace sdfvj
