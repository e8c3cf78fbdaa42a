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
    if (fade_.waiting) {
        FrameInputs old = in_;
        old.params = fade_.params;
        renderer_.Draw(*fade_.program, fade_.scene, old);
    } else {
        fieldMorph_.Draw(renderer_, in_, fade_.params, Ease(fade_.easing, t));
    }
    PresentRenderer(rw, rh, now);
    return true;
}

}  // namespace sdfvj
