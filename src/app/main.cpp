// sdfvj: a live SDF raymarching visualizer. This file only parses the command line; each command
// lives in cmd_*.cpp. Exit codes: 0 ok, 1 failed while running, 2 bad usage / nothing to run on.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "render/compile_process.h"
#include "isf/isf_server_post.h"
#include "render/render_process.h"
#ifdef SDFVJ_HAS_LIVE
#include "control/control.h"
#endif

using namespace sdfvj;

namespace {

// Options shared by render, live: scene, preset, effects, quality.
bool noProgramCache = false;   // --no-program-cache on render, live and bench reload

// A finite number of at least `lo` (above it when `strict`), for options a typo would otherwise turn into
// a table of zeros or a wait of -1 s; CLI11's PositiveNumber lets "nan" through.
CLI::Validator FiniteFrom(double lo, bool strict) {
    char what[32];
    std::snprintf(what, sizeof what, "%s %g", strict ? ">" : ">=", lo);
    return CLI::Validator(
        [lo, strict, desc = std::string(what)](std::string& text) -> std::string {
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            const bool ok = !text.empty() && end && *end == '\0' && std::isfinite(v) && (strict ? v > lo : v >= lo);
            return ok ? std::string() : "'" + text + "', expected a finite number " + desc;
        },
        what);
}

void AddShowOptions(CLI::App* cmd, ShowOptions* s) {
    cmd->add_flag("--no-program-cache", noProgramCache,
                  "compile every program; neither read nor write the on-disk program cache (also SDFVJ_PROGRAM_CACHE=0)");
    cmd->add_option("--scene", s->scene, "scene name (see `sdfvj list`) or a .glsl file");
    cmd->add_option("--preset", s->preset, "preset JSON (presets/NAME.json): scene, parameter values, effects, mapping");
    cmd->add_option("--effects", s->effects,
                    "effects over the scene's own, comma-separated: hard_shadows, soft_shadows, improved_shadows, ao, "
                    "specular, pbr, reflections=N, direct_reflections (a reflection lands on a surface lit without its shadow ray or AO, "
                    "in at most 48 steps: cheaper), quad_reflections (the reflection traced once per 2x2 pixels, through their centre, each pixel weighting it by its own "
                    "Fresnel term: with --render-scale 2, once per shown pixel; compute path), fog, fixed_step, ssaa (4 samples a pixel, each surface shaded once), ssaa_exact "
                    "(each sample shaded), heatmap, "
                    "depth, normals, work (map() calls a pixel, every phase, as a heatmap: 0 blue .. 127 red, log scale); none clears; -ao removes");
    cmd->add_option("--normals", s->normals, "normal method: central, forward or tetrahedron");
    cmd->add_option("--path", s->path, "render path: auto (timed probe, cached per GPU), compute or fragment")->capture_default_str();
    cmd->add_option("--param", s->params, "set a scene parameter, NAME=VALUE (repeatable; clamped to its range)");
    cmd->add_option("--steps", s->quality.maxSteps, "maximum raymarch steps")->capture_default_str();
    cmd->add_option("--eps", s->quality.hitEps, "hit epsilon, relative to distance travelled")->capture_default_str();
    cmd->add_option("--step-factor", s->quality.stepFactor, "step factor (below 1 under-relaxes)")->capture_default_str();
    cmd->add_option("--max-dist", s->quality.maxDist, "far distance")->capture_default_str();
    cmd->add_flag("--no-cone-prepass", [s](int64_t) { s->quality.conePrepass = false; },
                  "compute path: march every primary ray from the eye, without the 8x8-tile cone pre-pass "
                  "that starts it where its tile's cone met a surface (same image; for comparison)");
}

}  // namespace

int main(int argc, char** argv) {
    // Hidden: the compile process the show spawns of itself (render/compile_process.h); its
    // stdin and stdout are the job socket, so nothing else may print to stdout here.
    if (argc == 2 && std::string(argv[1]) == "compile-server") return RunCompileServer(0, 1);
    // Hidden: a render process (render/render_process.h); fd 3 is its socket.
    if (argc == 2 && std::string(argv[1]) == "render-server") return RunRenderServer(3, MakeIsfServerPost);
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    CLI::App app{
        "sdfvj — raymarch signed-distance-field scenes live from MIDI/OSC, or offline from a recorded take.\n\n"
        "Examples:\n"
        "  sdfvj list                                      scenes, presets and MIDI ports\n"
        "  sdfvj render --scene midi --size 640x360 --frames 60 --out out/\n"
        "  sdfvj render --preset demo --replay presets/demo_take.mid --video demo.mp4\n"
        "  sdfvj render --scene midi --post bloom,rgb_split --param amount=6   ISF post effects\n"
        "  sdfvj live --preset demo --midi LPD8            a window; knobs drive the scene\n"
        "  sdfvj bench --sizes 1920x1080                   GPU ms per frame, both render paths\n"};
    app.require_subcommand(1);

    RenderOptions render;
    auto* cmdRender = app.add_subcommand("render", "render frames headless (EGL, no display) to PNGs or a video");
    AddShowOptions(cmdRender, &render.show);
    cmdRender->add_option("--size", render.size, "frame size WxH")->capture_default_str();
    auto* framesOpt = cmdRender->add_option("--frames", render.frames, "frames to render (default: 1, or the whole take)")->check(FiniteFrom(1, false));
    cmdRender->add_option("--fps", render.fps, "frames per second of the fixed clock (time = frame / fps)")->capture_default_str();
    cmdRender->add_option("--out", render.out, "folder for frame_00000.png, ...")->capture_default_str();
    cmdRender->add_option("--replay", render.replay, "a Standard MIDI File whose events drive the parameters");
    cmdRender->add_option("--mapping", render.mapping, "mapping for --replay (default: the preset's, else generic_8knob)");
    cmdRender->add_option("--video", render.video, "pipe frames to ffmpeg (H.264) and write this .mp4 instead of PNGs; odd sizes are padded to even (libx264 needs them)");
    cmdRender->add_option("--post", render.show.post,
                          "ISF post effects over the frame, in order: names in shaders/isf (bloom, feedback_trails, "
                          "kaleidoscope, rgb_split, film_grain, edge_glow, color_grade, mirror) or .fs files, "
                          "comma-separated; --param sets their inputs too. --scene also takes an ISF or Shadertoy .fs "
                          "generator (docs/isf.md)");
    cmdRender->add_flag("--quiet", render.quiet, "no progress bar");
    cmdRender->add_option("--frame-range", render.frameRange,
                          "A:B (0-based, B included) or A: to the end: only these frames, byte-identical to the same "
                          "frames of the whole render; files keep their absolute index (docs/farm.md)");
    cmdRender->add_flag("--count-frames", render.countFrames, "print how many frames the whole render has and exit");
    cmdRender->add_flag("--evaluator", render.evaluator,
                        "draw the scene through its evaluator (the register machine of the evaluator tier, SDFVJ_EVALUATOR_TIER=1) instead of its compiled program: the same picture, hundreds of times slower");

    BenchOptions bench;
    auto* cmdBench = app.add_subcommand("bench", "GPU ms per frame: scenes x lighting tests x sizes x render paths");
    cmdBench->add_option("--scenes", bench.scenes, "scenes (default: all); NAME:literals times the literal tier of NAME (its float literals read from uniforms: what `live` shows first after a save that only retunes numbers); NAME:aoN draws NAME with N AO samples (default 5)")->delimiter(',');
    cmdBench->add_option("--sizes", bench.sizes, "sizes")->capture_default_str()->delimiter(',');
    cmdBench->add_option("--tests", bench.tests, "lighting tests: full, shadows_ao, shadows, none (default: these four); show = soft shadows, AO, specular, PBR and one reflection bounce; show_ssaa = show with 4 samples a pixel sharing each surface's shading; show_ssaa_exact = each sample shaded; show_direct = show with direct_reflections (the reflected surface lit without its shadow ray or AO, its march at most 48 steps); show_quad_reflections = show with quad_reflections (at 7680x4320: the bounce traced once per 4K pixel); full_quad_shade = full with quad_reflections (where the scene sets QUAD_SHADE_ALONE 1: its shadows and AO traced once per 2x2 pixels and lent to the pixels on their surface); where a frame goes: march = the cone pre-pass and the primary march alone (the depth view), normals = those and the normals (the normals view)")->delimiter(',');
    cmdBench->add_option("--paths", bench.paths, "render paths")->capture_default_str()->delimiter(',');
    cmdBench->add_option("--frames", bench.frames, "timed frames per cell (median)")->check(FiniteFrom(1, false))->capture_default_str();
    cmdBench->add_option("--warmup", bench.warmup, "untimed frames first")->check(FiniteFrom(0, false))->capture_default_str();
    cmdBench->add_option("--markdown", bench.markdown, "also write the table to this file");
    cmdBench->add_option("--csv", bench.csv, "also write the table as CSV: scene,lighting,size,path,ms,gpu");

    EffectsBenchOptions effectsBench;
    auto* cmdEffects = cmdBench->add_subcommand("effects", "each effect compiled out / compiled in but off / on");
    cmdEffects->add_option("--scene", effectsBench.scene, "scene")->capture_default_str();
    cmdEffects->add_option("--size", effectsBench.size, "frame size")->capture_default_str();
    cmdEffects->add_option("--path", effectsBench.path, "auto, compute or fragment")->capture_default_str();
    cmdEffects->add_option("--frames", effectsBench.frames, "timed rotations (median)")->check(FiniteFrom(1, false))->capture_default_str();
    cmdEffects->add_option("--warmup", effectsBench.warmup, "untimed rotations first")->check(FiniteFrom(0, false))->capture_default_str();
    cmdEffects->add_option("--markdown", effectsBench.markdown, "also write the table to this file");
    cmdEffects->add_option("--csv", effectsBench.csv, "also write the table as CSV: scene,lighting,size,path,ms,gpu,effect,variant");
    SsaaBenchOptions ssaaBench;
    auto* cmdSsaa = cmdBench->add_subcommand("ssaa", "ssaa's anti-aliasing: one sample, ssaa and ssaa_exact against a frame twice the size averaged 2x2; and that frame drawn with quad_reflections");
    cmdSsaa->add_option("--scenes", ssaaBench.scenes, "scenes (default: all)")->delimiter(',');
    cmdSsaa->add_option("--size", ssaaBench.size, "frame size (the truth is drawn at twice it)")->capture_default_str();
    cmdSsaa->add_option("--path", ssaaBench.path, "compute or fragment")->capture_default_str();
    cmdSsaa->add_option("--effects", ssaaBench.effects, "effects over each scene's own (as render --effects)")->capture_default_str();
    cmdSsaa->add_option("--markdown", ssaaBench.markdown, "also write the table to this file");
    WorkBenchOptions workBench;
    auto* cmdWork = cmdBench->add_subcommand("work", "where each pixel's map() calls go: the primary ray's march, normal, shadow ray and AO, and its "
                                                     "reflection's (mean per pixel; counts, the same on every device)");
    cmdWork->add_option("--scenes", workBench.scenes, "scenes (default: all)")->delimiter(',');
    cmdWork->add_option("--tests", workBench.tests, "lighting tests (as bench --tests, not march or normals)")->capture_default_str()->delimiter(',');
    cmdWork->add_option("--size", workBench.size, "frame size")->capture_default_str();
    cmdWork->add_option("--path", workBench.path, "compute or fragment")->capture_default_str();
    cmdWork->add_option("--markdown", workBench.markdown, "also write the table to this file");
    cmdWork->add_option("--csv", workBench.csv, "also write the table as CSV: scene,lighting,size,path,pixels_hit,primary_march,...,total");
    AccuracyBenchOptions accuracyBench;
    auto* cmdAccuracy = cmdBench->add_subcommand("accuracy", "quality knobs: GPU time against error vs a CPU double reference");
    cmdAccuracy->add_option("--scene", accuracyBench.scenes, "scenes, comma-separated, or all")->capture_default_str()->delimiter(',');
    cmdAccuracy->add_option("--size", accuracyBench.size, "frame size for timing and images")->capture_default_str();
    cmdAccuracy->add_option("--ref-size", accuracyBench.refSize, "size of the CPU double reference (geometry is compared there; default --size)");
    cmdAccuracy->add_option("--path", accuracyBench.path, "auto, compute or fragment")->capture_default_str();
    cmdAccuracy->add_option("--sweep", accuracyBench.sweep, "full (every knob, render scales too), tiny (a handful, for tests) scale (the default at render scales 0.25..1 and 2x2 supersampled, against the supersampled truth: the frame budget's resolution term) or looks (the default and the look rows, penumbra and AO samples, with their distance from the scene's look)")->capture_default_str();
    cmdAccuracy->add_option("--frames", accuracyBench.frames, "timed frames per setting (median)")->check(FiniteFrom(1, false))->capture_default_str();
    cmdAccuracy->add_option("--warmup", accuracyBench.warmup, "untimed frames first")->check(FiniteFrom(0, false))->capture_default_str();
    cmdAccuracy->add_option("--time", accuracyBench.time, "scene time in seconds")->capture_default_str();
    cmdAccuracy->add_option("--param", accuracyBench.params, "scene parameter NAME=VALUE (repeatable, clamped)");
    cmdAccuracy->add_option("--threads", accuracyBench.threads, "CPU reference threads (0: all cores)")->capture_default_str();
    cmdAccuracy->add_option("--out", accuracyBench.out, "folder for accuracy.csv, plots and accuracy.md")->capture_default_str();
    cmdAccuracy->add_option("--markdown", accuracyBench.markdown, "also write the report here (docs/accuracy.md)");
    cmdAccuracy->add_option("--csv", accuracyBench.csv, "also write the rows as CSV: scene,lighting,size,path,ms,gpu + the sweep's columns");
    SpirvBenchOptions spirvBench;
    auto* cmdSpirv = cmdBench->add_subcommand("spirv", "a scene's compute program built from GLSL and from SPIR-V (glslangValidator), "
                                                       "every step to its first use timed, the drivers' disk caches off");
    cmdSpirv->add_option("--scene", spirvBench.scene, "scene")->capture_default_str();
    cmdSpirv->add_option("--rounds", spirvBench.rounds, "builds of each form, interleaved (median)")->check(FiniteFrom(1, false))->capture_default_str();
    cmdSpirv->add_option("--glslang", spirvBench.glslang, "glslangValidator (default: beside sdfvj, then /usr/bin)");
    CompileBenchOptions compileBench;
    auto* cmdCompile = cmdBench->add_subcommand("compile", "where a driver's build time of a scene's program goes: the program built in cuts "
                                                           "(tier, effects, map() replaced by a sphere), every step to its first use timed, "
                                                           "the drivers' disk caches off");
    cmdCompile->add_option("--scene", compileBench.scene, "scene (a name or a .glsl file)")->capture_default_str();
    cmdCompile->add_option("--rounds", compileBench.rounds, "builds of each cut, interleaved (median)")->check(FiniteFrom(1, false))->capture_default_str();
    cmdCompile->add_option("--cuts", compileBench.cuts,
                           "TIER[/EFFECTS][@sphere][+NAME=VALUE]..[!HINT].. each: TIER optimized or quick (the first tier of a tiered build); "
                           "/EFFECTS on the scene's own, as --effects reads them (\"-ao,-soft_shadows\", \"none\"); @sphere: the scene's "
                           "map() replaced by a sphere on a plane (the renderer alone); +NAME=VALUE: a #define first (CONE_PREPASS=0); !HINT: #pragma optionNV(HINT), dashes as spaces (!unroll-none). "
                           "The first cut is the others' yardstick")
        ->capture_default_str();
    cmdCompile->add_option("--path", compileBench.path, "compute or fragment (the first use a 1x1 dispatch or draw)")->capture_default_str();
    cmdCompile->add_option("--csv", compileBench.csv, "also write the medians as CSV: scene,lighting,size,path,ms,gpu,cut,compile_ms,link_ms,use_ms,source_chars");
    PostBenchOptions postBench;
    auto* cmdPost = cmdBench->add_subcommand("post", "a post effect's save: save -> screen and the longest frame meanwhile, the chain "
                                                     "in contexts of its own (as live draws it) against the window's context");
    cmdPost->add_option("--effects", postBench.effects, "ISF effects, comma-separated (names in shaders/isf or .fs paths)")->capture_default_str();
    cmdPost->add_option("--size", postBench.size, "frame size")->capture_default_str();
    cmdPost->add_option("--rounds", postBench.rounds, "saves to time per way (interleaved)")->check(FiniteFrom(1, false))->capture_default_str();
    cmdPost->add_option("--frames", postBench.frames, "steady frames per way (10 interleaved blocks)")->check(FiniteFrom(1, false))->capture_default_str();
    cmdPost->add_option("--fps", postBench.fps, "pace frames like a display during saves (0: flat out)")->check(FiniteFrom(0, false))->capture_default_str();
    cmdPost->add_option("--csv", postBench.csv, "also write the rows as CSV: scene,lighting,size,path,ms,gpu + chain_in, save_to_screen_ms, longest_ms, swap_frame_ms, rounds");
    ResizeBenchOptions resizeBench;
    auto* cmdResize = cmdBench->add_subcommand("resize", "a change of the render scale (the resolution slider, --frame-budget): the frame "
                                                         "that makes it, with the targets of other sizes kept against new ones each time");
    cmdResize->add_option("--scene", resizeBench.scene, "scene")->capture_default_str();
    cmdResize->add_option("--size", resizeBench.size, "window size")->capture_default_str();
    cmdResize->add_option("--path", resizeBench.path, "compute or fragment")->capture_default_str();
    cmdResize->add_option("--scales", resizeBench.scales, "render scales visited in turn, the first the start (0.25..2)")->capture_default_str();
    cmdResize->add_option("--post", resizeBench.post, "an ISF chain over the scene, as live --post")->capture_default_str();
    cmdResize->add_option("--keep", resizeBench.keep, "other sizes the first way keeps")->capture_default_str();
    cmdResize->add_option("--rounds", resizeBench.rounds, "visits of every scale per way (interleaved)")->check(FiniteFrom(1, false))->capture_default_str();
    cmdResize->add_option("--fps", resizeBench.fps, "pace frames like a display (0: flat out)")->check(FiniteFrom(0, false))->capture_default_str();
    cmdResize->add_option("--csv", resizeBench.csv, "also write the rows as CSV: scene,lighting,size,path,ms,gpu + way, scale, first_change_ms, later_change_ms, after_ms");
    ReloadBenchOptions reloadBench;
    auto* cmdReload = cmdBench->add_subcommand("reload", "hot reload: save -> new program on screen, longest frame meanwhile");
    cmdReload->add_option("--scene", reloadBench.scene, "scene")->capture_default_str();
    cmdReload->add_option("--size", reloadBench.size, "frame size")->capture_default_str();
    cmdReload->add_option("--path", reloadBench.path, "auto, compute or fragment")->capture_default_str();
    cmdReload->add_option("--rounds", reloadBench.rounds, "saves to time")->capture_default_str();
    cmdReload->add_option("--driver-cache", reloadBench.driverCache,
                          "drivers' disk caches: off (MESA_SHADER_CACHE_DISABLE, __GL_SHADER_DISK_CACHE=0), fresh "
                          "(on, empty folders of this run) or warm (as set, warmed by an untimed pass)")
        ->capture_default_str();
    cmdReload->add_flag_callback("--warm-cache", [&] { reloadBench.driverCache = "warm"; }, "same as --driver-cache warm");
    cmdReload->add_option("--modes", reloadBench.modes, "compile modes: driver, worker, binary, process, process-source (the server builds it, the render thread then "
                          "compiles the same text for the drivers' disk caches to serve), warm (process + a loader thread that uses each binary once "
                          "before the hand-over), adopt (a new shared context per save compiles and uses the program, which is then "
                          "drawn on that context and presented on the render context), adopt-process (the same with the compile in the compile process), "
                          "stage (each program loaded, used and drawn by a thread of its own with a shared context), render-process (each program compiled, "
                          "used and drawn by a process of its own, its frames handed over on the GPU: a Vulkan-allocated image both "
                          "processes import (two, by turns) on a thread of their own, or a dma-buf; by shared memory where the driver offers neither; the frame shown one behind its inputs, so the server draws while "
                          "the show waits for the display), render-process-import-here (a new server's images imported and freed by the render thread, in a frame), render-process-no-touch (not used once on the import thread), render-process-free-here (freed by the render thread), render-process-reattach (each frame's image attached to one read framebuffer, not read through one kept per image), render-process-sync (the same, every frame a round trip), render-process-one-image (pipelined through one "
                          "image: each request waits for the show's read of the frame before), render-process-in-turn (tiered: the optimized build starts once the quick tier is on screen), render-process-standby (a spare holds the program on screen built, used and drawn, and a load of the same program, such as a --post save, takes it and builds only the chain), render-process-first-after-import (a new server's first frame asked for once its images are imported, which are made after its build: the way before session 41, two refreshes later), render-process+NAME=VALUE[+..] (render-process, these in its servers' "
                          "environment: SDFVJ_SERVER_PREPARE=0, no Vulkan device made ahead), render-process-shm (by shared memory always); MODE-evaluator for the modes that are not render-process (process-evaluator: a save is drawn at once by the scene's evaluator program, built ahead, with the save translated on the CPU, no driver build; the optimized program follows); comma-separated, rounds interleaved; "
                          "--first-frame: warm = with the loader")
        ->capture_default_str();
    cmdReload->add_option("--tiered", reloadBench.tiered, "quick tier first: auto (NVIDIA), on or off")->capture_default_str();
    cmdReload->add_option("--edit", reloadBench.edit,
                          "what each save changes: nudge (wraps the first constant in a sum: a new program to compile) or retune "
                          "(rewrites its value only: `live`'s literal tier shows it with no compile, the optimized program follows); "
                          "toggle: no save, effect pad hits instead (the six one-effect variants), cold against built ahead as live "
                          "does (prefetch), with and without a first use on the render context")
        ->check(CLI::IsMember({"nudge", "retune", "toggle"}))
        ->capture_default_str();
    cmdReload->add_option("--post", reloadBench.post,
                          "render-process modes only: the servers draw each frame through these ISF post effects (as live "
                          "--render-process --post does), and each save gives the last of them a new function instead of "
                          "editing the scene: what a post effect's save costs the show when the render processes build it")
        ->type_name("A,B");
    cmdReload->add_option("--fps", reloadBench.fps, "pace frames like a display (0: flat out)")->check(FiniteFrom(0, false))->capture_default_str();
    cmdReload->add_flag("--first-frame", reloadBench.firstFrame,
                        "time one launch instead: context -> first frame, with the program cache (run twice)");
    cmdReload->add_flag("--no-program-cache", noProgramCache, "compile every program; neither read nor write the program cache");
#ifdef SDFVJ_HAS_LIVE
    double inputSeconds = 60;
    auto* cmdInput = cmdBench->add_subcommand("input", "event-to-frame latency and a 10,000 msg/s flood (OSC + MIDI)");
    cmdInput->add_option("--seconds", inputSeconds, "flood duration")->check(FiniteFrom(0, true))->capture_default_str();
#endif

    app.add_subcommand("list", "list scenes, presets and MIDI ports");
    app.add_subcommand("info", "the GL driver and what it offers sdfvj, the shader caches, the data and cache folders");

#ifdef SDFVJ_HAS_LIVE
    LiveOptions live;
    auto* cmdLive = app.add_subcommand("live", "open a window and perform: MIDI and OSC drive the scene");
    AddShowOptions(cmdLive, &live.show);
    cmdLive->add_option("--size", live.size, "window size WxH")->capture_default_str();
    cmdLive->add_flag("--fullscreen", live.fullscreen, "fullscreen on the primary monitor");
    cmdLive->add_option("--midi", live.midi, "MIDI input port: name substring or index (default: all, plus virtual port 'sdfvj')");
    cmdLive->add_option("--osc-port", live.oscPort, "OSC UDP port")->capture_default_str();
    cmdLive->add_option("--osc-feedback", live.oscFeedback, "send values back to HOST:PORT on preset changes");
    cmdLive->add_option("--mapping", live.mapping, "controller mapping TOML (default: the preset's, else generic_8knob)");
    cmdLive->add_option("--record", live.record, "record incoming MIDI and OSC to this .mid");
    cmdLive->add_option("--replay", live.replay, "play a take into the show in real time (rehearsal)");
    cmdLive->add_option("--audio", live.audio,
                        "audio input through JACK: a port to connect from (system:capture_1), or 'in' for an "
                        "unconnected port sdfvj-audio:in; its level, bands, onsets and beat drive mapping entries "
                        "(audio = \"bass\"), ISF audio inputs and the recorder (docs/audio.md)");
    cmdLive->add_option("--post", live.show.post,
                        "ISF post effects over the frame (as for render; else the preset's \"post\"); their inputs "
                        "are parameters for OSC, mappings and the overlay; saved .fs files reload");
    cmdLive->add_option("--seconds", live.seconds, "quit after this many seconds (0: run until closed)")->check(FiniteFrom(0, false));
    cmdLive->add_option("--screenshot", live.screenshot,
                        "write the last frame to this PNG on exit (with --seconds, a show that has drawn no frame yet "
                        "runs on until it has, at most 30 s more)");
    cmdLive->add_option("--log-params", live.logParams,
                        "append one line per frame to this file, \"TIME name=value ...\": the values the frame "
                        "renders, after mapping and smoothing (for tests, and for debugging a mapping)");
    cmdLive->add_flag("--hide-overlay", live.hideOverlay,
                      "start with the overlay hidden, as after Tab (clean screenshots); Tab shows it");
    cmdLive->add_option("--sync", live.sync,
                        "mtc: the show clock (automation, u_time, the take, --log-params) follows MIDI Time Code from any "
                        "input port; a jump seeks, a lost master freewheels then stops. clock: MIDI clock sets tempo and beat")
        ->check(CLI::IsMember({"mtc", "clock", "wall"}));
    cmdLive->add_option("--forward", live.forward,
                        "HOST:PORT[,HOST:PORT...]: re-send as OSC every parameter, preset and effect the show applies to "
                        "follower nodes (other `sdfvj live`), and the whole state once a second (docs/sync.md)");
    cmdLive->add_option("--frame-budget", live.frameBudgetMs, "keep frames under MS: about once a second the best setting of the accuracy sweep's front that fits (docs/performance.md; 0: off)")
        ->check(FiniteFrom(0, false));
    cmdLive->add_option("--hitch-ms", live.hitchMs,
                        "say a frame longer than MS (at most a line a second, the longest): how much of it the show's "
                        "thread ran, waited for a CPU (a loaded machine) or was blocked (the GPU, a render process), and "
                        "its longest stages (0: off)")
        ->check(FiniteFrom(0, false))->capture_default_str();
    cmdLive->add_flag("--warm-ahead", live.warmAhead,
                      "sound check: every variant an effect pad or a preset reaches is built ahead AND drawn once as it "
                      "arrives, so the next hit shows it in one frame. On NVIDIA that first draw freezes the picture "
                      "(0.6 s midi, 1.5 s character on an H200) once per variant, after 3 s with nothing asked for: "
                      "run it before the doors open. Without it variants are still built ahead on a GPU, and a hit "
                      "waits for that first draw instead (0.3-0.6 s)");
    cmdLive->add_flag("--render-process", live.renderProcess,
                      "draw the scene in a render process of its own: a save, an effect pad or a new size builds its "
                      "program in a spare process while the one on screen goes on, so no frame waits for a compile "
                      "(on NVIDIA a save otherwise stalls the show 150-300 ms). Scene changes morph or crossfade as "
                      "in-process, each drawn by a process of its own; the variants pads and presets reach are built "
                      "ahead into the program cache by another (a pad hit on an H200: 0.3-0.5 s, no frame held); "
                      "\"measure costs\" is timed by the process on screen (docs/performance.md, \"Session 18\"). On a GPU the "
                      "--post chain is drawn there too (a post effect's save builds in a spare; a chain with feedback stays here, "
                      "where its trails outlive every swap), and a spare holds the "
                      "program on screen ready, so a post save or a new size builds only what changed "
                      "(SDFVJ_POST_IN_SERVER, SDFVJ_STANDBY=1|0; docs/isf.md)");
    cmdLive->add_option("--budget-floor", live.budgetFloor, "never below, e.g. scale=0.5,steps=64,shadow_steps=16,ao=2");
    cmdLive->add_option("--render-scale", live.renderScale,
                        "render the scene at this fraction of the window, upscaled (0.25..1; the overlay's "
                        "'resolution' slider changes it live): a slow machine keeps its frame rate. Above 1 it "
                        "supersamples: 2 draws twice the width and height and shows each pixel as the mean of 2x2 "
                        "(edges without stairs, 4x the cost; add the effect quad_reflections to trace the mirror bounce once per "
                        "shown pixel: 3-24 % faster on an H100, docs/performance.md \"Session 47\")")
        ->check(CLI::Range(0.25, 2.0))
        ->capture_default_str();
    cmdLive->footer(
        "In the window: Tab hides the overlay (for the audience), F11 toggles fullscreen, 1-9 pick presets, "
        "a mouse drag orbits the camera and 0 puts it back, Esc quits. The overlay edits values, learns a "
        "control (click 'learn', move a knob), saves presets, toggles effects and shows the last MIDI/OSC "
        "events. Saving a shader, mapping or preset reloads it; a broken save keeps the last good one and "
        "prints file:line. Presets may script parameters (docs/presets.md).");

    std::string learnParam, learnMapping = "mappings/learned.toml";
    double learnTimeout = 30;
    auto* cmdLearn = app.add_subcommand("learn", "MIDI learn: wait for the next control that moves and map it");
    cmdLearn->footer("Listens on every MIDI input port and on OSC UDP port 9000; when 9000 is taken (a running "
                     "`sdfvj live`), on a free port, printed at start. The mapping file is changed only when the "
                     "new entry parses, and atomically (a temporary file renamed over it): on any error it is left "
                     "byte-identical.");
    cmdLearn->add_option("--param", learnParam, "parameter to map")->required();
    cmdLearn->add_option("--mapping", learnMapping, "mapping file to add the entry to (all or nothing)")->capture_default_str();
    cmdLearn->add_option("--timeout", learnTimeout, "seconds to wait")->check(FiniteFrom(0, true))->capture_default_str();
#endif

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    render.framesGiven = framesOpt->count() > 0;
    if (noProgramCache) setenv("SDFVJ_PROGRAM_CACHE", "0", 1);

    if (cmdRender->parsed()) return RunRender(render);
    if (cmdAccuracy->parsed()) {
        for (int i = 0; i < argc; ++i) accuracyBench.commandLine += (i ? " " : "") + std::string(i ? argv[i] : "sdfvj");
        return RunAccuracyBench(accuracyBench);
    }
    if (cmdEffects->parsed()) return RunEffectsBench(effectsBench);
    if (cmdSsaa->parsed()) return RunSsaaBench(ssaaBench);
    if (cmdWork->parsed()) return RunWorkBench(workBench);
    if (cmdSpirv->parsed()) return RunSpirvBench(spirvBench);
    if (cmdCompile->parsed()) return RunCompileBench(compileBench);
    if (cmdPost->parsed()) return RunPostBench(postBench);
    if (cmdResize->parsed()) return RunResizeBench(resizeBench);
    if (cmdReload->parsed()) return RunReloadBench(reloadBench);
#ifdef SDFVJ_HAS_LIVE
    if (cmdInput->parsed()) return RunInputBench(inputSeconds);
#endif
    if (cmdBench->parsed()) return RunBench(bench);
#ifdef SDFVJ_HAS_LIVE
    if (cmdLive->parsed()) return RunLive(live);
    if (cmdLearn->parsed()) return RunLearn(learnParam, learnMapping, learnTimeout);
#endif
    if (app.got_subcommand("info")) return RunInfo();
    if (app.got_subcommand("list")) {
        int rc = RunList();
#ifdef SDFVJ_HAS_LIVE
        std::printf("MIDI input ports:\n");
        auto ports = ListMidiPorts();
        if (ports.empty()) std::printf("  (none: no controller connected, or no MIDI system)\n");
        for (size_t i = 0; i < ports.size(); ++i) std::printf("  %zu: %s\n", i, ports[i].c_str());
#endif
        return rc;
    }
    return 2;
}
