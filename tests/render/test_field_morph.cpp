// Field morph: a scene change that interpolates the two fields in one program (seed 003),
// mix(map_from(p), map_to(p), t), marched with the mixed Lipschitz bound.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "gl_fixture.h"
#include "render/field_morph.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

SceneInfo Scene(const std::string& name) {
    SceneInfo s;
    std::string err;
    INFO(err);
    REQUIRE(FindScene(name, &s, &err));
    return s;
}

ParamValues Defaults(const SceneInfo& s) {
    ParamValues v;
    for (const ParamDecl& d : s.params) v.emplace_back(d.name, d.defaultValue);
    return v;
}

// The morph from `a` to `b` at t, drawn into a w x h frame.
Image DrawMorph(FieldMorph& morph, const SceneInfo& b, float t, int w, int h, const Quality& q = {}) {
    FrameRenderer fr;
    std::string err;
    REQUIRE(fr.Resize(w, h, &err));
    FrameInputs in;
    in.time = 1.0;
    in.quality = q;
    in.params = Defaults(b);
    morph.Draw(fr, in, Defaults(morph.From()), t);
    return Image{w, h, fr.ReadPixels()};
}

}  // namespace

TEST_CASE("field morph: every pair of shipped scenes compiles into one morph program", "[field_morph]") {
    RequireGl();
    const std::vector<std::pair<std::string, std::string>> pairs = {
        {"midi", "primitives"}, {"primitives", "character"}, {"character", "mandelbulb"}, {"mandelbulb", "midi"}};
    for (const auto& [a, b] : pairs) {
        const SceneInfo sa = Scene(a), sb = Scene(b);
        FieldMorph morph;
        morph.Prepare(sa, sb, UnionEffects(sa.effects, sb.effects), RenderPath::Fragment);
        INFO(a << " -> " << b << ": " << morph.Error());
        CHECK(morph.Wait() == FieldMorph::State::Ready);
        // Both scenes' inputs are there, renamed, and the morph knob itself.
        const auto uniforms = morph.Current() ? morph.Current()->ActiveUniforms() : std::vector<std::string>{};
        CHECK(std::find(uniforms.begin(), uniforms.end(), "u_morph") != uniforms.end());
    }
}

TEST_CASE("field morph: t = 0 draws the first scene, t = 1 the second, half way neither nor their frame average",
          "[field_morph]") {
    RequireGl();
    const int w = 320, h = 180;
    const SceneInfo a = Scene("midi"), b = Scene("primitives");
    const EffectSet fx = UnionEffects(a.effects, b.effects);
    FieldMorph morph;
    morph.Prepare(a, b, fx, RenderPath::Fragment);
    INFO(morph.Error());
    REQUIRE(morph.Wait() == FieldMorph::State::Ready);

    const Image ia = RenderScene("midi", fx, RenderPath::Fragment, w, h);
    const Image ib = RenderScene("primitives", fx, RenderPath::Fragment, w, h);
    const Image m0 = DrawMorph(morph, b, 0.0f, w, h), m1 = DrawMorph(morph, b, 1.0f, w, h);
    const Image half = DrawMorph(morph, b, 0.5f, w, h);
    std::filesystem::create_directories(SDFVJ_TEST_OUTPUT_DIR);
    SavePng(SDFVJ_TEST_OUTPUT_DIR "/field_morph_0.png", m0);
    SavePng(SDFVJ_TEST_OUTPUT_DIR "/field_morph_50.png", half);
    SavePng(SDFVJ_TEST_OUTPUT_DIR "/field_morph_100.png", m1);

    // The ends: the same field, marched inside one bounding sphere around both scenes instead of
    // the scene's own, so step positions (and the last bits of soft shadows) may differ slightly.
    const ImageDiff d0 = CompareImages(ia, m0, 8), d1 = CompareImages(ib, m1, 8);
    CHECK(d0.meanAbs < 1.0);
    CHECK(d0.fractionOver < 0.01);
    CHECK(d1.meanAbs < 1.0);
    CHECK(d1.fractionOver < 0.01);

    // Half way is a third picture: not either scene, and not the crossfade of their frames.
    CHECK(CompareImages(ia, half, 8).fractionOver > 0.05);
    CHECK(CompareImages(ib, half, 8).fractionOver > 0.05);
    Image avg = ia;
    for (size_t i = 0; i < avg.rgba.size(); ++i) avg.rgba[i] = (uint8_t)((ia.rgba[i] + ib.rgba[i] + 1) / 2);
    CHECK(CompareImages(avg, half, 16).fractionOver > 0.05);
}

TEST_CASE("field morph: a field and the character morph on the compute path too: the cell table and the frame state are filled, t = 0 draws the scene",
          "[field_morph]") {
    RequireGl();
    const int w = 160, h = 90;
    // field150: its cell table in shared memory (SCENE_SETUP_LANES); character: its skeleton stored
    // once per frame (SCENE_STATE_FRAME) from the morph's combined sceneSetup().
    for (const char* name : {"field150", "character"}) {
        const SceneInfo a = Scene(name), b = Scene("midi");
        const EffectSet fx = UnionEffects(a.effects, b.effects);
        FieldMorph morph;
        morph.Prepare(a, b, fx, RenderPath::Compute);
        INFO(name << ": " << morph.Error());
        REQUIRE(morph.Wait() == FieldMorph::State::Ready);
        if (std::string(name) == "character") CHECK(morph.Current()->FrameState());
        // The morph first: on llvmpipe a group's shared memory may still hold what the scene's own
        // program left there.
        const Image m0 = DrawMorph(morph, b, 0.0f, w, h);
        const Image ia = RenderScene(name, fx, RenderPath::Compute, w, h);
        // An empty table (every cell a sphere on the floor, no wave) or skeleton moves most of it.
        const ImageDiff d0 = CompareImages(ia, m0, 8);
        CHECK(d0.meanAbs < 1.0);
        CHECK(d0.fractionOver < 0.01);
    }
}

TEST_CASE("field morph: the mixed Lipschitz bound never oversteps: hits agree with quarter-length steps",
          "[field_morph]") {
    RequireGl();
    const int w = 96, h = 54;
    // midi's raw field (SCENE_GLOBAL_LIPSCHITZ: the blob is not divided by its own bound, the
    // marcher divides by sceneLipschitz() instead) at a stress setting, strong twist and
    // displacement: bound near 6, into the 1-Lipschitz character. Only the mixed bound keeps it safe.
    const SceneInfo a = Scene("midi"), b = Scene("character");
    EffectSet geometry;
    geometry.debugView = 4;   // float target: t of the hit, or -1 on a miss
    ShaderSource src;
    std::string err;
    REQUIRE(AssembleMorphProgram(a, b, VariantKey{b.path, geometry, RenderPath::Fragment}, &src, &err));
    src.text.insert(src.text.find('\n') + 1, "#define SCENE_GLOBAL_LIPSCHITZ 1\n");
    Program program, wrong;
    INFO(err);
    REQUIRE(program.Build(src, RenderPath::Fragment, &err));
    // The control: the same morph claiming the smaller of the two bounds must overstep, or this
    // test could not see an overstep at all.
    const std::string mixed = "mix(m0_sceneLipschitz(), m1_sceneLipschitz(), u_morph)";
    const size_t at = src.text.find(mixed);
    REQUIRE(at != std::string::npos);
    src.text.replace(at, mixed.size(), "min(m0_sceneLipschitz(), m1_sceneLipschitz())");
    REQUIRE(wrong.Build(src, RenderPath::Fragment, &err));
    ParamValues stress = Defaults(a);
    for (auto& [n, v] : stress) {
        if (n == "twist") v = 3.0f;
        if (n == "scale") v = 2.0f;
        if (n == "displacement") v = 0.25f;
    }
    auto hits = [&](const Program& prog, float t, float stepFactor, int steps) {
        FrameRenderer fr;
        std::string err;
        REQUIRE(fr.Resize(w, h, &err, true));
        FrameInputs in;
        in.time = 1.0;
        in.quality.stepFactor = stepFactor;
        in.quality.maxSteps = steps;
        in.params = Defaults(b);
        FrameInputs mixed = in;
        mixed.params = MorphParamValues(stress, in.params, t);
        fr.Draw(prog, MixSceneInfo(a, b, t), mixed);
        return fr.ReadPixelsFloat();
    };
    // Hits that disagree with quarter-length steps, of hits compared.
    auto disagreement = [&](const Program& prog, float t, int* compared, int* nonFinite) {
        const std::vector<float> fast = hits(prog, t, 1.0f, 1024), safe = hits(program, t, 0.25f, 4096);
        int disagree = 0;
        *compared = *nonFinite = 0;
        for (size_t i = 0; i < fast.size(); i += 4) {
            if (!std::isfinite(fast[i]) || !std::isfinite(safe[i])) ++*nonFinite;
            if (safe[i] <= 0.0f && fast[i] <= 0.0f) continue;   // both miss
            ++*compared;
            // An overstep goes through a surface: a miss, or a hit much further along the ray.
            if (fast[i] <= 0.0f || safe[i] <= 0.0f || std::abs(fast[i] - safe[i]) > 0.02f * safe[i] + 0.01f) ++disagree;
        }
        return disagree;
    };
    for (float t : {0.25f, 0.5f, 0.75f}) {
        int compared = 0, nonFinite = 0;
        const int disagree = disagreement(program, t, &compared, &nonFinite);
        INFO("t = " << t << ": " << disagree << " of " << compared << " hits disagree");
        CHECK(nonFinite == 0);
        CHECK(compared > (int)(w * h) / 4);
        CHECK(disagree <= compared / 200);   // 0.5 %: silhouette pixels may graze differently
    }
    int compared = 0, nonFinite = 0;
    const int wrongDisagree = disagreement(wrong, 0.1f, &compared, &nonFinite);
    INFO("claiming the smaller bound: " << wrongDisagree << " of " << compared << " hits disagree");
    CHECK(wrongDisagree > compared / 50);
}
