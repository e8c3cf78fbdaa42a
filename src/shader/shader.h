// Shader module: turns a scene + effect set + render path into one GLSL source string.
//
// GLSL has no #include, so we expand it here, emitting `#line N S` after every file switch;
// S indexes ShaderSource::files, which is how a driver's "0:42(5): error" becomes
// "shaders/scenes/midi.glsl:42: error" (MapCompileLog). The same file list is what hot reload
// watches. Nothing here touches GL.
#pragma once
#include <string>
#include <vector>

#include "scene/scene.h"

namespace sdfvj {

enum class RenderPath { Fragment, Compute };
const char* RenderPathName(RenderPath p);

// Everything that selects a distinct compiled program. Uniform values are not part of it.
struct VariantKey {
    std::string scenePath;
    EffectSet effects;
    RenderPath path = RenderPath::Fragment;
    auto operator<=>(const VariantKey&) const = default;
};

struct ShaderSource {
    std::string text;                // the complete program source, #version first
    std::vector<std::string> files;  // index = #line source-string number; [0] is "<generated>"
    uint64_t hash = 0;               // FNV-1a of text: same hash, same program
    std::vector<float> literals;     // AssembleProgram(..., liftLiterals): the values of u_lit[i]
};

// Expands `#include "path"` (relative to shaders/, then to the including file), each file once.
// On failure: "file:line: what is wrong".
// liftLiterals: `path`'s own float literals (not its includes') become u_lit[i] (literals.h) and
// their values go to out->literals.
bool ExpandIncludes(const std::string& path, ShaderSource* out, std::string* error, bool liftLiterals = false);

// The scene's input uniforms as every program declares them: `uniform float u_<NAME>;` per header
// input, in header order (bool and int inputs are floats too). AssembleProgram and the evaluator's
// unit (evaluator.h AssembleEvaluatorUnit) share it, so both read the same uniforms.
std::string SceneInputUniforms(const SceneInfo& scene);

// Builds the program source for a variant: version, effect #defines, built-in uniforms, the
// scene's generated parameter uniforms, the scene, render.glsl and the path's main().
// liftLiterals: the scene file's float literals become `uniform float u_lit[N]` (literals.h): two
// saves that differ only in those numbers assemble the same text (same hash), with the values in
// out->literals (LiveProgram's literal tier draws a retuned scene with no compile).
bool AssembleProgram(const SceneInfo& scene, const VariantKey& key, ShaderSource* out, std::string* error,
                     bool liftLiterals = false);

// A program whose field morphs from scene `from` to scene `to` (seed 003's scene interpolation):
//   map(p) = mix(map_from(p), map_to(p), u_morph),  sceneLipschitz() = mix(L_from, L_to, u_morph)
// (the gradient of a mix is at most the mix of the bounds, so every step stays safe). Each scene
// is included once with its map/sceneLipschitz/sceneBound/mapGround and its inputs renamed by the
// preprocessor: `from`'s input NAME becomes uniform u_m0_NAME, `to`'s u_m1_NAME. Where both scenes
// declare a bounding sphere and agree on a ground, the morph bounds both with one sphere. Two scenes
// that define the same helper name do not compile together: the caller falls back to a crossfade.
// key.scenePath is ignored; key.effects and key.path select the variant.
bool AssembleMorphProgram(const SceneInfo& from, const SceneInfo& to, const VariantKey& key, ShaderSource* out,
                          std::string* error);

// The #defines a variant compiles with, one "NAME VALUE" per entry (also used by tests).
std::vector<std::string> VariantDefines(const EffectSet& e, RenderPath path);

// Rewrites a driver's compile log so each message names the file and line the performer edited.
// Understands Mesa ("0:42(5): error: ...") and NVIDIA ("0(42) : error C0000: ...") formats.
std::string MapCompileLog(const std::string& log, const ShaderSource& src);

// The data-root-relative form of a path, for messages ("shaders/scenes/midi.glsl").
std::string DisplayPath(const std::string& path);

uint64_t HashBytes(const std::string& bytes);

// A vertex shader that draws one full-screen triangle from gl_VertexID (no buffers).
const char* FullscreenVertexShader();

}  // namespace sdfvj
