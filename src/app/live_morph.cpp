// `live`: a preset switch to another scene with a morph time morphs the two fields in one
// program (render/field_morph.h) where both scenes allow it, else crossfades their frames.
// The morph program compiles beside the next scene's before the switch starts; until it is ready
// the old scene stays on screen, so no frame waits for a compile.
#include <epoxy/gl.h>

#include "app/live_app.h"
#include "automation/automation.h"

namespace sdfvj {

namespace {
constexpr double kMorphCompileWait = 5.0;   // seconds the old scene holds before crossfading instead
}  // namespace

// Called when the show asks for another variant: where the scene changes with a field morph,
// the morph program starts compiling now, beside the new scene's own.
void LiveSession::PrepareFieldMorph() {
    const MorphDesc& how = state_.show.preset.automation.morph;
    if (!live_.Current() || state_.wanted.scenePath == live_.Key().scenePath) return;   // effects only
    fieldMorph_.Reset();
    if (how.seconds <= 0 || how.easing == Easing::Cut || !how.fieldMorph) return;
    SceneInfo to;
    std::string error;
    if (!LoadScene(state_.wanted.scenePath, &to, &error)) return;   // LiveProgram reports it
    fieldMorph_.Prepare(live_.Scene(), to, UnionEffects(live_.Key().effects, state_.wanted.effects), state_.wanted.path);
}

// Whether the fade that starts now morphs the fields (the morph program is for this pair).
bool LiveSession::FadeMorphsFields() {
    const FieldMorph::State s = fieldMorph_.Poll();
    if (s == FieldMorph::State::Idle || fieldMorph_.From().path != shownScene_.path ||
        fieldMorph_.To().path != live_.Scene().path)
        return false;
    if (s == FieldMorph::State::Failed) {
        const std::string& e = fieldMorph_.Error();
        state_.report.Say("sdfvj live: " + shownScene_.name + " and " + live_.Scene().name +
                          " cannot morph as one field (" + e.substr(0, e.find('\n')) + ") — crossfading their frames");
        fieldMorph_.Reset();
        return false;
    }
    state_.report.Say("scene morph: " + shownScene_.name + " -> " + live_.Scene().name + " as one field over " +
                      std::to_string(fade_.seconds).substr(0, 4) + " s" +
                      (s == FieldMorph::State::Compiling ? " (its program is still compiling)" : ""));
    return true;
}

// Draws this frame of a field morph into renderer_ and the window; false when the fade is not a
// field morph (or just fell back to a crossfade), and the caller draws as usual.
bool LiveSession::DrawFieldFade(double now, int rw, int rh) {
    if (!fade_.program || !fade_.field) return false;
    const FieldMorph::State s = fieldMorph_.Poll();
    if (s == FieldMorph::State::Ready && fade_.waiting) {
        fade_.waiting = false;
        fade_.start = now;   // the morph runs its whole time from the first frame it can draw
    }
    const bool late = s == FieldMorph::State::Compiling && now - fade_.start > kMorphCompileWait;
    if (s == FieldMorph::State::Failed || late) {
        state_.report.Say(std::string("sdfvj live: the field morph ") +
                          (late ? "is still compiling" : "did not compile") + " — crossfading the frames instead");
        fade_.field = fade_.waiting = false;
        fade_.start = now;
        fieldMorph_.Reset();
        return false;
    }
    const double t = fade_.waiting ? 0.0 : (now - fade_.start) / fade_.seconds;
    if (t >= 1.0) {
        fieldMorph_.Reset();
        fade_ = Fade{};
        return false;   // done: the new scene alone from now on
    }
    FrameHitch::Scope timed(&hitch_, "draw: field morph");
    if (fade_.waiting) {
        FrameInputs old = in_;
        old.params = fade_.params;
        renderer_.Draw(*fade_.program, fade_.scene, old);
    } else {
        fieldMorph_.Draw(renderer_, in_, fade_.params, Ease(fade_.easing, t));
    }
    timed.Done();
    PresentRenderer(rw, rh, now);
    return true;
}

}  // namespace sdfvj

namespace sdfvj {

// --render-process: when the show asks for another scene with a field morph, a server held for it
// builds the two fields' program beside the new scene's own (LiveServers::PrepareMorph).
void LiveSession::PrepareServerMorph() {
    if (state_.wanted.scenePath == servers_->Key().scenePath && !fade_.field && servers_->MorphState() != LiveServers::Morph::None) {
        servers_->DropMorph();   // asked for and then not used (the show went back, or the scene did not build)
        serverMorphFor_ = VariantKey{};
        return;
    }
    if (state_.wanted == serverMorphFor_ || state_.wanted.scenePath == servers_->Key().scenePath || !servers_->OnScreen()) return;
    serverMorphFor_ = state_.wanted;
    const MorphDesc& how = state_.show.preset.automation.morph;
    if (how.seconds <= 0 || how.easing == Easing::Cut || !how.fieldMorph || state_.show.isfScene) return;
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    servers_->PrepareMorph(state_.wanted, Scaled(w), Scaled(h));
}

// Whether the fade that starts now morphs the fields (a morph was built for this pair); fade_ is set.
bool LiveSession::ServerFadeMorphsFields() {
    const LiveServers::Morph s = servers_->MorphState();
    if (s == LiveServers::Morph::None || !servers_->MorphFor(fade_.scene.path, servers_->Scene().path)) return false;
    if (s == LiveServers::Morph::Failed) {
        const std::string& e = servers_->MorphError();
        state_.report.Say("sdfvj live: " + fade_.scene.name + " and " + servers_->Scene().name + " cannot morph as one field (" +
                          e.substr(0, e.find('\n')) + ") — crossfading their frames");
        servers_->DropMorph();
        return false;
    }
    fade_.field = true;
    fade_.waiting = s != LiveServers::Morph::Ready;
    state_.report.Say("scene morph: " + fade_.scene.name + " -> " + servers_->Scene().name + " as one field over " +
                      std::to_string(fade_.seconds).substr(0, 4) + " s, drawn by a render process" +
                      (fade_.waiting ? " (its program is still building)" : ""));
    return true;
}

// This frame of a field morph drawn by its server, to the window; false when the fade is not one
// (or just fell back to a crossfade, or ended), and the caller draws as usual.
bool LiveSession::DrawServerFieldFade(double now) {
    if (!fade_.server || !fade_.field) return false;
    const LiveServers::Morph s = servers_->MorphState();
    if (s == LiveServers::Morph::Ready && fade_.waiting) {
        fade_.waiting = false;
        fade_.start = now;   // the morph runs its whole time from the first frame it can draw
    }
    const bool late = s == LiveServers::Morph::Building && now - fade_.start > kMorphCompileWait;
    if (s == LiveServers::Morph::Failed || s == LiveServers::Morph::None || late) {
        state_.report.Say(std::string("sdfvj live: the field morph ") + (late ? "is still building" : "did not build") +
                          " — crossfading the frames instead");
        fade_.field = fade_.waiting = false;
        fade_.start = now;
        servers_->DropMorph();
        return false;
    }
    const double t = fade_.waiting ? 0.0 : (now - fade_.start) / fade_.seconds;
    if (t >= 1.0) {
        servers_->DropMorph();
        fade_ = Fade{};
        servers_->DropPrevious();
        return false;   // done: the new scene alone from now on
    }
    FrameInputs in = in_;
    unsigned texture = 0;
    if (fade_.waiting) {   // the scene before holds, drawn by its own server
        in.params = fade_.params;
        Guard("draw: the scene before's frame", [&] { texture = servers_->PreviousFrame(in); });
    } else {
        in.params = MorphParamValues(fade_.params, in_.params, Ease(fade_.easing, t));
        Guard("draw: the morph's frame", [&] { texture = servers_->MorphFrame(in); });
    }
    if (!texture) return false;
    const ServerLoad& size = fade_.waiting ? servers_->Servers().PreviousLoad() : servers_->Servers().PreparedLoad(ServerShow::Held::Morph);
    PresentServerTexture(texture, size.width, size.height, now);
    return true;
}

}  // namespace sdfvj
