// Scene module: finds scene files and presets, and parses their ISF-style JSON headers.
//
// A scene file (shaders/scenes/NAME.glsl) opens with a JSON header in a comment:
//   /*{ "NAME": "midi", "INPUTS": [ {"NAME": "twist", "TYPE": "float", ...} ],
//       "EFFECTS": {"SHADOWS": "soft", "AO": true, ...}, "CAMERA": {...}, "LIGHT": {...} }*/
// The header is the one place a parameter is declared: uniforms, mapping validation and the
// overlay all read the ParamDecl list made here.
#pragma once
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/automation_desc.h"
#include "core/param_decl.h"

namespace sdfvj {

using Vec3f = std::array<float, 3>;

// The effects a program is compiled with. Zero-initialised means "nothing": no shadows, no AO.
// Every field becomes a #define; an effect that is 0 is not in the program at all.
// A reflection's step budget under `direct_reflections` (render.glsl BOUNCE_STEPS).
constexpr int kDirectReflectionSteps = 48;
// The compute path's frame state (main_comp.glsl SCENE_STATE_FRAME): the buffer binding (uniform and
// storage) of the blocks AssembleProgram generates from a scene's SCENE_STATE globals, and the size
// FrameRenderer gives it (std140; 16 KB, the smallest GL_MAX_UNIFORM_BLOCK_SIZE GL allows).
constexpr int kSceneStateBinding = 2;
// The evaluator program's storage buffers (render/eval.glsl): its code and its constants
// (shader/evaluator.h), bound by Program::BindEvaluator.
constexpr int kEvalCodeBinding = 5;
constexpr int kEvalConstBinding = 6;
constexpr int kSceneStateBytes = 16384;

struct EffectSet {
    int shadows = 0;        // 0 none, 1 hard, 2 soft, 3 improved soft
    bool ao = false;
    bool specular = false;  // Blinn-Phong highlight
    bool pbr = false;       // Cook-Torrance instead of Lambert + Blinn-Phong
    int reflections = 0;    // bounce count
    bool fog = false;
    int debugView = 0;      // 0 off, 1 step heatmap, 2 depth, 3 normals; 4-7 float views, 8 work heatmap (render.glsl DEBUG_VIEW)
    int normals = 0;        // 0 central, 1 forward, 2 tetrahedron
    bool marchFixed = false;
    bool directReflections = false;   // `direct_reflections`: a reflection lands on a surface lit without its shadow ray or AO, in at most 48 steps (render.glsl BOUNCE_LIGHT 2, BOUNCE_STEPS 48)
    bool quadReflections = false;   // `quad_reflections`: the bounce traced once per 2x2 pixels (quad_reflections.glsl QUAD_REFLECTIONS; compute path)
    int supersample = 0;   // 1 `ssaa`: 4 samples a pixel, shading shared per surface; 2 `ssaa_exact`: each sample shaded (render/supersample.glsl)
    auto operator<=>(const EffectSet&) const = default;
};

struct SceneInfo {
    std::string name;
    std::string path;          // absolute path of the .glsl file
    std::string description;
    std::vector<ParamDecl> params;
    EffectSet effects;         // what the scene calls for
    Vec3f camPos{0, 1, -5}, camTarget{0, 0, 0};
    float fov = 45.0f;
    Vec3f lightDir{0.577f, 0.577f, -0.577f}, lightColor{1, 1, 1};
    float roughness = 0.5f, metalness = 0.0f;
};

// Where shaders/, presets/ and mappings/ live: $SDFVJ_ROOT, else the source tree we were built from.
std::string DataRoot();

// Parses a scene's header. On failure returns false and sets error to
// "path:line: what is wrong, what was expected".
// Every field is type- and range-checked (numbers finite and in range, strings strings, CAMERA,
// LIGHT, MATERIAL and EFFECTS objects with known keys only), nesting is limited to 64 levels and
// the header to 1 MiB; no exception leaves it. Unknown top-level keys are accepted (ISF headers
// carry others: ISFVSN, CREDIT, ...), except a known key in the wrong case ("Inputs").
bool LoadScene(const std::string& path, SceneInfo* out, std::string* error);
// LoadScene on text already in memory (the whole .glsl); `path` is used for out->path and errors.
// The fuzzer (src/scene/fuzz_scene.cpp) calls this, the code production runs.
bool ParseSceneText(const std::string& text, const std::string& path, SceneInfo* out, std::string* error);

// A scene by name ("midi") or by file path. Error lists the known scenes.
bool FindScene(const std::string& nameOrFile, SceneInfo* out, std::string* error);
// The file FindScene reads: a path as given (it has a '/' or ends in .glsl), else shaders/scenes/NAME.glsl.
std::string SceneFile(const std::string& nameOrFile);

// Names of the scenes in shaders/scenes, sorted.
std::vector<std::string> ListScenes();

// Effect names as used on the command line and in presets: "soft_shadows", "ao", ...
// Applies a comma-separated list on top of `base` ("none" clears everything first).
bool ParseEffectList(const std::string& list, EffectSet* effects, std::string* error);
std::string DescribeEffects(const EffectSet& e);  // the inverse, for logs and bench tables
// "central" | "forward" | "tetrahedron"
bool ParseNormalMethod(const std::string& name, int* method, std::string* error);

// The four lighting tests of the seed thesis: full (soft shadows + AO + specular),
// soft shadows + AO, soft shadows, none.
struct LightingTest { const char* name; EffectSet effects; };
std::vector<LightingTest> SeedLightingTests();
// The six variants an effect pad reaches from `e`: shadows (soft), AO, specular, fog, PBR and one
// reflection bounce, each switched (what `live` builds ahead, and `bench reload --edit toggle` times).
std::vector<EffectSet> OneEffectToggles(const EffectSet& e);
// Issue 13's heaviest target: soft shadows, AO, specular, PBR and one reflection bounce
// (`bench --tests show`; not among the seed's four, so not in a bare `bench`).
LightingTest ShowLightingTest();
// The show lighting with 4x supersampling that shares each surface's shading between the samples
// (`ssaa`; `bench --tests show_ssaa`, at 3840x2160 the 4x supersampled 4K of issue 13); `exact`:
// every sample shaded (`ssaa_exact`, show_ssaa_exact).
LightingTest ShowSupersampledLightingTest(bool exact);
// The show lighting with `quad_reflections` (`bench --tests show_quad_reflections`): at 7680x4320 the
// 4x supersampled 4K's bounce traced once per shown pixel.
LightingTest ShowQuadReflectionsLightingTest();
// The seed's full lighting with `quad_reflections` (`bench --tests full_quad_shade`): with no bounce
// to trace, the quads' pass runs only where the scene sets QUAD_SHADE_ALONE 1 (quad_reflections.glsl),
// its centres' shadows and occlusion lent to the pixels on their surface; elsewhere it draws as full.
LightingTest FullQuadShadeLightingTest();
// The show lighting with `direct_reflections` (`bench --tests show_direct`): the reflected surface
// lit directly, unshadowed and unoccluded, its march at most 48 steps.
LightingTest ShowDirectReflectionsLightingTest();
// Where a frame goes, part by part (`bench --tests march normals none full`): "march", the cone
// pre-pass and the primary march alone (the depth view: no normal, albedo or light is computed);
// "normals", those and the surface normal (the normals view).
std::vector<LightingTest> FramePartTests();

// A preset: a scene with parameter values and effect overrides, optionally a mapping and a take.
struct Preset {
    std::string path;
    std::string scene;
    std::map<std::string, float> params;
    std::string effects;       // effect list as for --effects, applied over the scene's own
    std::string normals;
    std::string mapping;       // path relative to the data root
    std::string take;          // path relative to the data root
    std::string post;          // ISF post chain, as for --post: "bloom,mirror" or .fs paths (src/isf)
    AutomationDesc automation; // scripted parameters, envelopes, cues, tempo, morph (automation module)
};
// Presets are strict: unknown keys are errors (with their line), params are finite numbers
// (or booleans), effects and normals must parse. Errors are "path:line: what, expected ...".
bool LoadPreset(const std::string& path, Preset* out, std::string* error);
// LoadPreset on JSON text already in memory (fuzzer entry); `path` is used for errors.
bool ParsePresetText(const std::string& text, const std::string& path, Preset* out, std::string* error);
std::vector<std::string> ListPresets();

}  // namespace sdfvj
