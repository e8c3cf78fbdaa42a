// FieldMorph: a scene change that morphs the fields themselves (seed 003's scene interpolation)
// rather than the two frames: one program marches mix(map_from(p), map_to(p), t), so shapes melt
// into each other with their lighting, shadows and reflections recomputed every frame.
//
//   morph.Prepare(fromScene, toScene, effects, path);   // compiles in the background
//   each frame: if (morph.Poll() == FieldMorph::State::Ready)
//       morph.Draw(renderer, in, fromParams, t);        // in.params: the `to` scene's values
//
// Where the two scenes cannot share a program (a helper both define) Poll() says Failed with the
// compile log, and the caller crossfades the frames instead. Render thread only (GL).
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "render/render.h"

namespace sdfvj {

using ParamValues = std::vector<std::pair<std::string, float>>;

// The header a morph frame is drawn with: camera, light and material mixed by t, and the inputs
// of both scenes (from's as m0_NAME, to's as m1_NAME) plus `morph` (0..1), so FrameRenderer sets
// and clamps them as it does any scene's.
SceneInfo MixSceneInfo(const SceneInfo& from, const SceneInfo& to, float t);
// The values for MixSceneInfo's inputs: from's and to's values renamed, and morph = t.
ParamValues MorphParamValues(const ParamValues& from, const ParamValues& to, float t);
// What a morph compiles with: every effect either scene has (the larger count where they differ).
EffectSet UnionEffects(const EffectSet& a, const EffectSet& b);

class FieldMorph {
public:
    enum class State { Idle, Compiling, Ready, Failed };
    // Starts compiling the morph from `from` to `to` (a different scene file). Replaces any
    // morph in progress.
    void Prepare(const SceneInfo& from, const SceneInfo& to, const EffectSet& effects, RenderPath path);
    // Finishes the compile when the driver (or the compile worker) has it; never blocks.
    State Poll();
    // Blocks until the compile is done (offline renders, tests).
    State Wait();
    void Reset();
    // Draws the morph at t (0 = from, 1 = to). `in.params` holds the to-scene's values.
    void Draw(FrameRenderer& renderer, const FrameInputs& in, const ParamValues& fromParams, float t) const;
    const SceneInfo& From() const { return from_; }
    const SceneInfo& To() const { return to_; }
    const std::string& Error() const { return error_; }
    const Program* Current() const { return program_.get(); }

private:
    void Finish();
    SceneInfo from_, to_;
    State state_ = State::Idle;
    PendingProgram pending_;
    std::unique_ptr<Program> program_;
    std::string error_;
};

}  // namespace sdfvj
