// The sdfvj commands. Each returns the process exit code: 0 ok, 1 failed while running,
// 2 bad usage or nothing to run on (unknown scene, bad size, no GL).
#pragma once
#include <string>
#include <vector>

#include "app/show.h"

namespace sdfvj {

struct RenderOptions {
    ShowOptions show;
    std::string size = "640x360";
    int frames = 1;            // 0 = the whole take when replaying
    bool framesGiven = false;
    double fps = 30.0;
    std::string out = "out";
    std::string replay;        // .mid take (full build only)
    std::string mapping;       // mapping for the replay; default: preset's, else generic profile
    std::string video;         // pipe to ffmpeg
    bool quiet = false;
    std::string frameRange;    // "A:B" (inclusive), "A:" to the end: only these frames, the same bytes
                               // as in the whole render (docs/farm.md)
    bool countFrames = false;  // print the whole render's frame count and exit (no GL)
    bool evaluator = false;    // draw the scene through its evaluator program (shader/eval_program.h)
};
int RunRender(const RenderOptions& o);

struct BenchOptions {
    std::vector<std::string> scenes;   // empty = all
    std::vector<std::string> sizes = {"640x480", "1280x720", "1600x1024", "1920x1080", "3840x2160"};
    std::vector<std::string> tests;    // lighting tests by name; empty = all four
    std::vector<std::string> paths = {"fragment", "compute"};
    int frames = 10;
    int warmup = 3;
    std::string markdown;              // also write the table here
    std::string csv;                   // and as CSV (scene,lighting,size,path,ms,gpu)
};
int RunBench(const BenchOptions& o);
// `sdfvj info`: the GL context, driver features, the shader caches and sdfvj's folders (cmd_info.cpp).
int RunInfo();

// `sdfvj bench effects --scene S`: each effect (a) compiled out, (b) compiled in but switched
// off by a uniform, (c) on — GPU time of each, interleaved in one run.
struct EffectsBenchOptions {
    std::string scene = "midi";
    std::string size = "1920x1080";
    std::string path = "auto";
    int frames = 20;
    int warmup = 3;
    std::string markdown;
    std::string csv;                   // scene,lighting,size,path,ms,gpu,effect,variant
};
int RunEffectsBench(const EffectsBenchOptions& o);

// `sdfvj bench ssaa`: one sample, `ssaa` and `ssaa_exact` against a frame twice the size averaged
// 2x2 (cmd_bench_ssaa.cpp).
struct SsaaBenchOptions {
    std::vector<std::string> scenes;   // default: all
    std::string size = "640x360";
    std::string path = "compute";
    std::string effects = "pbr,reflections=1";
    std::string markdown;
};
int RunSsaaBench(const SsaaBenchOptions& o);

// `sdfvj bench work`: where each pixel's map() calls go (render.glsl DEBUG_VIEW 6 and 7), per scene
// and lighting test: the mean per pixel of the primary ray's march, normal, shadow ray and AO, and
// of its reflection's. Counts, not time: the same on every device.
struct WorkBenchOptions {
    std::vector<std::string> scenes;   // default: all
    std::vector<std::string> tests = {"full", "show"};
    std::string size = "480x270";
    std::string path = "compute";
    std::string markdown;
    std::string csv;
};
int RunWorkBench(const WorkBenchOptions& o);

// `sdfvj bench accuracy --scene S`: every quality knob swept; GPU time and error against the CPU
// double reference (geometry) and a 4096-step GPU render (image). CSV, plots, docs/accuracy.md.
struct AccuracyBenchOptions {
    std::vector<std::string> scenes = {"midi"};   // --scene, comma-separated; "all" = the four
    std::string size = "1920x1080";
    std::string refSize;                          // CPU reference size (default: --size)
    std::string path = "auto";
    std::string sweep = "full";                   // full | tiny
    int frames = 10;
    int warmup = 3;
    double time = 1.0;
    std::vector<std::string> params;              // NAME=VALUE
    int threads = 0;
    std::string out = "out/accuracy";             // accuracy.csv, accuracy_<scene>.png/.svg, accuracy.md
    std::string markdown;                         // also write the report here (e.g. docs/accuracy.md)
    std::string csv;                              // rows as scene,lighting,size,path,ms,gpu + the sweep's columns
    std::string commandLine;                      // recorded in the report
};
int RunAccuracyBench(const AccuracyBenchOptions& o);

// `sdfvj bench spirv`: a scene's compute program built from GLSL and from SPIR-V (glslangValidator).
struct SpirvBenchOptions {
    std::string scene = "midi";
    int rounds = 5;
    std::string glslang;   // glslangValidator's path ("" : beside sdfvj, then /usr/bin)
};
int RunSpirvBench(const SpirvBenchOptions& o);

// `sdfvj bench compile`: a scene's compute program built in cuts (tier, effects, map() replaced by a
// sphere, renderer #defines), every step to its first use timed: where a driver's build time goes.
struct CompileBenchOptions {
    std::string scene = "midi";
    int rounds = 5;
    std::vector<std::string> cuts = {"quick", "optimized", "quick@sphere", "quick/none", "quick/none@sphere"};
    std::string path = "compute";   // or fragment
    std::string csv;   // also write the medians as CSV
};
int RunCompileBench(const CompileBenchOptions& o);

// `sdfvj bench post`: a post effect's save, the chain in contexts of its own against the window's.
struct PostBenchOptions {
    std::string effects = "bloom,feedback_trails";
    std::string size = "1920x1080";
    int rounds = 5;
    int frames = 200;    // steady frames per way (10 interleaved blocks)
    double fps = 60;     // frames paced like a display during saves; 0: flat out
    std::string csv;
};
int RunPostBench(const PostBenchOptions& o);

// `sdfvj bench resize`: a change of the render scale, the frame that makes it (cmd_bench_resize.cpp).
struct ResizeBenchOptions {
    std::string scene = "character";
    std::string size = "1920x1080";
    std::string path = "compute";
    std::string scales = "1,0.7,0.5,0.85";
    std::string post;    // ISF chain over the scene, as `live --post`
    int keep = 4;        // sizes kept by the first way
    int rounds = 4;
    double fps = 60;
    std::string csv;
};
int RunResizeBench(const ResizeBenchOptions& o);

// `sdfvj bench reload`: save -> first frame with the new program, and the longest frame meanwhile.
struct ReloadBenchOptions {
    std::string scene = "midi";
    std::string size = "640x360";
    std::string path = "auto";
    int rounds = 5;
    std::string driverCache = "off";              // off | fresh (empty folders) | warm (--warm-cache)
    std::string modes = "driver,worker,binary";   // compile modes to measure, in order
    std::string tiered = "auto";                  // auto (NVIDIA) | on | off
    double fps = 60;                              // frames paced like a display; 0: flat out
    bool firstFrame = false;                      // one launch's first frame instead of reloads
    std::string edit = "nudge";                   // nudge (a structural edit: compiles) | retune (numbers only: the literal tier)
                                                  // | toggle (effect pad hits, cmd_bench_toggle.cpp)
    std::string post;                             // render-process modes: the servers' post chain; each save edits its last file
};
int RunReloadBench(const ReloadBenchOptions& o);
// --edit toggle (cmd_bench_toggle.cpp): effect pad hits, cold against built ahead; after the
// drivers' caches are set, before any context exists.
// With "render-process" in --modes: the hits as live --render-process takes them
// (bench_toggle_servers.cpp); with it alone, only those.
int RunToggleBench(const ReloadBenchOptions& o, const SceneInfo& scene, int w, int h, const std::string& cacheLine);
int RunServerToggleWays(const ReloadBenchOptions& o, const SceneInfo& scene, RenderPath path, const std::vector<VariantKey>& toggles,
                        int w, int h);

int RunList();

#ifdef SDFVJ_HAS_LIVE
struct LiveOptions {
    ShowOptions show;
    std::string size = "1280x720";
    bool fullscreen = false;
    std::string midi;                   // port substring or index
    std::string audio;                  // JACK audio input: "" off, "in" an unconnected port, else the port to connect from
    int oscPort = 9000;
    std::string oscFeedback;
    std::string mapping;
    std::string record;
    std::string replay;
    double seconds = 0;                 // quit after this long (0 = run until closed)
    std::string screenshot;             // write the last frame here on exit
    std::string logParams;              // append "time name=value ..." per frame to this file
    bool hideOverlay = false;           // start with the overlay hidden (as after Tab)
    double renderScale = 1.0;           // the scene renders at this fraction of the window (0.25..1; 2: 2x2 supersampled)
    double frameBudgetMs = 0;           // > 0: keep frames under this (frame_budget.h)
    double hitchMs = 100;               // > 0: say a frame longer than this, and where its time went (frame_hitch.h)
    bool warmAhead = false;             // variants built ahead are also finished on the render context (live_prefetch.cpp)
    std::string budgetFloor;            // never below: "scale=0.5,steps=64,shadow_steps=16,ao=2"
    std::string sync;                   // "mtc": the show clock follows MIDI Time Code; "clock": MIDI clock (live_sync.h)
    std::string forward;                // "HOST:PORT[,...]": re-send what the show applies as OSC (live_forward.h)
    bool renderProcess = false;         // the scene drawn by render processes (live_servers.h)
};
int RunLive(const LiveOptions& o);
#endif

}  // namespace sdfvj
