// Show: what the frame loop renders — a scene, its effect variant, its parameter values and the
// program compiled for them. Shared by `render`, `live` and `bench`.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "render/render.h"
#include "scene/scene.h"

namespace sdfvj {

struct Show;

// Options every rendering command takes. Zero/empty means "the scene's or preset's own".
struct ShowOptions {
    std::string scene;        // name or .glsl path
    std::string preset;       // presets/NAME.json or a path
    std::string effects;      // --effects list, applied over the scene's (and preset's)
    std::string normals;      // --normals central|forward|tetrahedron
    std::string path = "auto";
    std::vector<std::string> params;   // --param name=value
    std::string post;         // --post: ISF post chain ("bloom,mirror" or .fs paths); else the preset's
    Quality quality;
    // live: the show on stage. A preset for the scene on stage, or keeping the post chain on stage,
    // reads that file's last good header from here when the file no longer parses (a save mid-edit):
    // the preset applies, and Show::notices says what was read instead.
    const Show* onStage = nullptr;
};

struct Show {
    SceneInfo scene;
    Preset preset;            // empty unless a preset was given
    EffectSet effects;        // the variant being rendered
    RenderPath path = RenderPath::Fragment;
    std::vector<std::pair<std::string, float>> params;   // starting values, clamped (post inputs too)
    std::string post;                   // the ISF post chain: --post, else the preset's "post"
    std::vector<ParamDecl> postDecls;   // its inputs: presets, --param, OSC and mappings set them by name
    bool isfScene = false;              // the scene is an ISF or Shadertoy generator: the first stage of `post`
    Quality quality;
    std::vector<std::string> notices;   // "file:line: ... — the show's last good header stands in" (ShowOptions::onStage)
    std::unique_ptr<Program> program;
};

// Every parameter of a show: the scene's inputs, then its post chain's (a name both have is one).
std::vector<ParamDecl> ShowDecls(const Show& show);

// Resolves scene and preset and parses every option (no GL needed). Errors are one line.
bool PrepareShow(const ShowOptions& opts, Show* show, std::string* error);
// Picks the render path (probe when "auto") and builds the program. Needs a current GL context.
// --path: compute, fragment, or probed (the probe's log printed when verbose).
void PickRenderPath(Show* show, const std::string& pathOption, bool verbose);
bool BuildShow(Show* show, const std::string& pathOption, std::string* error, bool verbose);

// Parses "WxH".
bool ParseSize(const std::string& text, int* w, int* h, std::string* error);
// A bench's frame: its size (ParseSize) and a path named "compute" or "fragment" (no auto).
bool ParseSizeAndPath(const std::string& size, const std::string& path, int* w, int* h, RenderPath* rp, std::string* error);

// A one-line progress bar on stderr: frames done, frames per second, time left.
void PrintProgress(int done, int total, double elapsedSeconds);

}  // namespace sdfvj
