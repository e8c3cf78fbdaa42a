// The scene evaluator's GPU program (issue 12): the renderer with the scene's hook functions
// calling the register machine of render/eval.glsl (specified in shader/evaluator.h), so one
// program per scene *shape* draws any save that only changes what the hooks compute: the save's
// code is uploaded (Program::SetEvaluatorCode), no driver build.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "shader/shader.h"

namespace sdfvj {

// The same program AssembleProgram builds for `key`, with the scene's text replaced by its *stub*
// (EvaluatorStub) and render/eval.glsl in front of it; `#define SCENE_EVALUATOR 1`,
// SCENE_SETUP_FRAME 0, SCENE_TABLES 0 (the machine runs the setup per invocation and keeps no
// shared tables), ONE_SITE 1 (render/one_site.glsl: one call site of the field, so the machine is
// inlined once there) and CONE_PREPASS 0 right after #version (as QuickTierText adds its defines).
// Two saves whose text differs only inside function bodies assemble the same text (same hash).
// false with a one-line reason when the scene's top level cannot be stubbed (the scene is then
// not evaluated: its saves compile as before).
// unroll: instructions per iteration of the machine's loop in a field hook (1, 2, 4, 8 or 16;
// render/eval.glsl EV_UNROLL). 1 on a GPU. llvmpipe stops a shader's loops after 65535 iterations
// in all, which a pixel of mandelbulb or a field scene runs past at 1: kEvaluatorUnrollSoftware
// there, at several times the build (each call site of a field hook is a copy of the machine).
constexpr int kEvaluatorUnrollSoftware = 4;
bool AssembleEvaluatorProgram(const SceneInfo& scene, const VariantKey& key, ShaderSource* out, std::string* error,
                              int unroll = 1);

// The stub of an expanded scene (`text`: ExpandIncludes output, `#line N S` directives naming
// ShaderSource::files indices; `sceneFile`: the scene file's index): every definition of a hook
// (eval::HookNames(): map, mapGround, ..., sceneSetup), in whichever file, keeps its header and gets
// the body `{ return evalMap(p); }` (render/eval.glsl); every other function defined in the scene
// file itself is removed, as are its comments and blank lines; top-level declarations, #defines,
// #if structure, SCENE_STATE lines and macros stay, as does every included file's other text.
// The scene file's own #line directives become `#line 1 S` (its line numbers move with any edit
// of a body above them). false with "file: what" when the text is not what the scanner reads for
// certain (unbalanced braces, a preprocessor line in a function's header, a #define inside a body
// it drops, a hook with another signature, no hook at all).
bool EvaluatorStub(const std::string& text, int sceneFile, const std::vector<std::string>& files, std::string* out,
                   std::string* error);

// A compute program (64 invocations a group) that runs the machine for the tests: invocation i
// reads the point `vec4 probeIn[i]` (storage buffer binding 0), runs evalPrepare() (the scene's
// setup, the argument-less hooks) and writes 8 vec4s to `probeOut[8 i ..]` (binding 1): map,
// mapGround, mapObjects at the point, sceneBound, sceneLipschitz, sceneGroundBlend, sceneBoxMin,
// sceneBoxMax. With eval::Run on the same code it shows the GPU and CPU machines agree.
bool AssembleEvaluatorProbe(const SceneInfo& scene, ShaderSource* out, std::string* error);

// The opcodes as render/eval.glsl names them (EV_<NAME>, from the C++ enum) with their values:
// what AssembleEvaluatorProgram declares in front of eval.glsl. For the test that keeps the two
// in step.
const std::vector<std::pair<std::string, uint32_t>>& EvaluatorOpConstants();

}  // namespace sdfvj
