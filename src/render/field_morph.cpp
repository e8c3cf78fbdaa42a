#include "render/field_morph.h"

#include <algorithm>
#include <cmath>

namespace sdfvj {

namespace {

Vec3f Mix(const Vec3f& a, const Vec3f& b, float t) {
    return {a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t};
}

void AddRenamed(const std::vector<ParamDecl>& decls, const char* prefix, std::vector<ParamDecl>* out) {
    for (ParamDecl d : decls) {
        d.name = std::string(prefix) + "_" + d.name;
        out->push_back(std::move(d));
    }
}

}  // namespace

SceneInfo MixSceneInfo(const SceneInfo& from, const SceneInfo& to, float t) {
    t = std::clamp(t, 0.0f, 1.0f);
    SceneInfo s = to;
    s.name = from.name + ">" + to.name;
    s.camPos = Mix(from.camPos, to.camPos, t);
    s.camTarget = Mix(from.camTarget, to.camTarget, t);
    s.fov = from.fov + (to.fov - from.fov) * t;
    Vec3f l = Mix(from.lightDir, to.lightDir, t);
    const float n = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    s.lightDir = n > 1e-6f ? Vec3f{l[0] / n, l[1] / n, l[2] / n} : to.lightDir;
    s.lightColor = Mix(from.lightColor, to.lightColor, t);
    s.roughness = from.roughness + (to.roughness - from.roughness) * t;
    s.metalness = from.metalness + (to.metalness - from.metalness) * t;
    s.params.clear();
    AddRenamed(from.params, "m0", &s.params);
    AddRenamed(to.params, "m1", &s.params);
    ParamDecl morph;
    morph.name = "morph";
    morph.defaultValue = 0.0f;
    morph.minValue = 0.0f;
    morph.maxValue = 1.0f;
    morph.label = "Morph";
    s.params.push_back(morph);
    return s;
}

ParamValues MorphParamValues(const ParamValues& from, const ParamValues& to, float t) {
    ParamValues v;
    v.reserve(from.size() + to.size() + 1);
    for (const auto& [name, value] : from) v.emplace_back("m0_" + name, value);
    for (const auto& [name, value] : to) v.emplace_back("m1_" + name, value);
    v.emplace_back("morph", t);
    return v;
}

EffectSet UnionEffects(const EffectSet& a, const EffectSet& b) {
    EffectSet e = b;
    e.shadows = std::max(a.shadows, b.shadows);
    e.ao = a.ao || b.ao;
    e.specular = a.specular || b.specular;
    e.pbr = a.pbr || b.pbr;
    e.reflections = std::max(a.reflections, b.reflections);
    e.fog = a.fog || b.fog;
    return e;
}

void FieldMorph::Prepare(const SceneInfo& from, const SceneInfo& to, const EffectSet& effects, RenderPath path) {
    Reset();
    from_ = from;
    to_ = to;
    ShaderSource src;
    VariantKey key{to.path, effects, path};
    if (from.path == to.path || !AssembleMorphProgram(from, to, key, &src, &error_)) {
        if (error_.empty()) error_ = "a field morph needs two different scenes";
        state_ = State::Failed;
        return;
    }
    pending_.Begin(src, path);
    state_ = State::Compiling;
}

void FieldMorph::Finish() {
    auto program = std::make_unique<Program>();
    std::string log;
    if (pending_.Finish(program.get(), &log)) {
        program_ = std::move(program);
        state_ = State::Ready;
    } else {
        error_ = log.empty() ? "the morph program did not link" : log;
        state_ = State::Failed;
    }
}

FieldMorph::State FieldMorph::Poll() {
    if (state_ == State::Compiling && pending_.Ready()) Finish();
    return state_;
}

FieldMorph::State FieldMorph::Wait() {
    if (state_ == State::Compiling) Finish();
    return state_;
}

void FieldMorph::Reset() {
    pending_.Cancel();
    program_.reset();
    error_.clear();
    state_ = State::Idle;
}

void FieldMorph::Draw(FrameRenderer& renderer, const FrameInputs& in, const ParamValues& fromParams, float t) const {
    if (state_ != State::Ready || !program_) return;
    FrameInputs mixed = in;
    mixed.params = MorphParamValues(fromParams, in.params, t);
    renderer.Draw(*program_, MixSceneInfo(from_, to_, t), mixed);
}

}  // namespace sdfvj
