// `sdfvj bench reload`: how long a saved shader takes to reach the screen, and what the reload
// does to frame times. Works on a copy of shaders/ in a temp folder. Each round saves the scene
// the way an editor does (temp file renamed over it) with its first constant nudged by a
// per-run nonce: a program no cache has seen, so the round measures a compile, not a cache hit
// (a comment would not do: the same text every run, and compilers drop comments before their
// caches' keys are taken). The drivers' disk caches are off unless asked for (`--driver-cache`).
// Frames are paced like a display (`--fps`, 0: flat out). Per round: save -> first tier on
// screen, save -> optimized program on screen, the longest frame meanwhile, and which part of a
// frame was long (the reload step, i.e. LiveProgram::Update, or the first draw of the new program).
//
// `--first-frame`: instead of reloads, one launch: context, program (from the on-disk program
// cache when an earlier launch stored it), first frame drawn. Run it twice for the second launch.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <unistd.h>

#include "app/bench_adopt.h"
#include "app/bench_first_frame.h"
#include "app/bench_reload_report.h"
#include "app/bench_render_process.h"
#include "app/bench_stage.h"
#include "app/bench_support.h"
#include "app/commands.h"
#include "render/compile_process.h"
#include "render/compile_worker.h"
#include "render/gl_stages.h"
#include "render/live_program.h"
#include "render/program_cache.h"
#include "shader/literals.h"
#include "shader/watch.h"

namespace fs = std::filesystem;

namespace sdfvj {

namespace {

int Fail(const std::string& what, int code = 2) { return ReloadBenchFail(what, code); }

}  // namespace

int RunReloadBench(const ReloadBenchOptions& o) {
    std::string error;
    int w = 0, h = 0;
    if (!ParseSize(o.size, &w, &h, &error)) return Fail(error);
    SceneInfo scene;
    if (!FindScene(o.scene, &scene, &error)) return Fail(error);
    if (o.driverCache != "off" && o.driverCache != "fresh" && o.driverCache != "warm")
        return Fail("--driver-cache '" + o.driverCache + "', expected off, fresh or warm");
    if (o.tiered != "auto" && o.tiered != "on" && o.tiered != "off")
        return Fail("--tiered '" + o.tiered + "', expected auto, on or off");
    if (o.rounds < 1) return Fail("--rounds must be at least 1");
    const fs::path root = fs::temp_directory_path() / ("sdfvj-bench-reload-" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root);
    struct Cleanup { fs::path p; ~Cleanup() { std::error_code ec; fs::remove_all(p, ec); } } cleanup{root};
    const std::string cacheLine = SetDriverCaches(o.driverCache, root / "driver-cache", o.firstFrame);
    if (o.firstFrame) return ReloadFirstFrame(o, scene, w, h, cacheLine);
    if (o.edit == "toggle") return RunToggleBench(o, scene, w, h, cacheLine);

    HeadlessContext gl;
    if (!gl.Create(&error)) return Fail(error);
    fs::copy(fs::path(DataRoot()) / "shaders", root / "shaders", fs::copy_options::recursive);
    const std::string oldRoot = DataRoot();
    setenv("SDFVJ_ROOT", root.c_str(), 1);
    struct RestoreRoot { std::string p; ~RestoreRoot() { setenv("SDFVJ_ROOT", p.c_str(), 1); } } restoreRoot{oldRoot};
    const fs::path sceneFile = root / "shaders" / "scenes" / fs::path(scene.path).filename();
    std::string original;
    {
        std::ifstream in(sceneFile, std::ios::binary);
        std::stringstream ss;
        ss << in.rdbuf();
        original = ss.str();
    }
    // warm: the same saves every run, so the caches hold them; otherwise new ones every run.
    const uint64_t nonce = o.driverCache == "warm" ? 0 : (uint64_t)Clock::now().time_since_epoch().count() / 1000;
    bool nudged = false;
    const bool retune = o.edit == "retune";
    const LiftedText lifted = LiftLiterals(original);
    auto saveText = [&](int round) {
        const double delta = 1e-6 * (double)(1 + (nonce + (uint64_t)round * 7919) % 100000);
        if (retune && !lifted.values.empty()) return RetuneFirstConstant(original, lifted.values[0] + delta, &nudged);
        return NudgeFirstConstant(original, delta, &nudged);
    };
    saveText(0);
    const BenchPostSaves postSaves(o.post, root, nonce);   // --post
    const std::vector<std::string>& post = postSaves.paths;
    auto save = [&](int round) { return post.empty() ? SaveLikeAnEditor(sceneFile, saveText(round)) : postSaves.Save(round); };
    GLint binaryFormats = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &binaryFormats);
    std::printf("# sdfvj bench reload: %s at %dx%d on %s\n", scene.name.c_str(), w, h, gl.Description().c_str());
    std::printf("driver disk caches: %s; program binary formats: %d; program cache: %s; full-screen draws: %s\n", cacheLine.c_str(),
                binaryFormats, ProgramCacheEnabled() ? ProgramCacheFolder().c_str() : "off",
                OverwriteBlendOn() ? "the identity blend (llvmpipe builds one function a program)" : "blending off");
    if (!post.empty()) std::printf("post chain (drawn by the render processes): %s\n", o.post.c_str());
    std::printf("each save: %s; frames paced at %s\n",
                !post.empty() ? "the post chain's last file gets a new function (a new program every run); the scene stays"
                : nudged ? retune ? "the scene's first constant retuned, its value only (the literal tier shows it; a new optimized "
                                  "program every run)"
                                : "the scene's first constant nudged (a new program every run)"
                       : "NO constant to nudge in this scene: a comment is appended (caches may serve it)",
                o.fps > 0 ? (std::to_string((int)o.fps) + " Hz").c_str() : "flat out");

    // Every mode is set up first (its own compile process, worker, loader, watcher, program and
    // target), then the rounds are interleaved: round 1 of every mode, then round 2, ..., so a
    // machine that gets busier or quieter moves every mode's figures alike.
    struct ModeRun {
        int mode = 0;
        bool standby = false;   // render-process-standby: ServerShow::SetStandby
        bool evaluator = false;   // MODE-evaluator
        int entry = 0;   // its place in --modes, from 1: what each save's nudge is made of
        std::string name;
        std::unique_ptr<CompileProcess> process;
        std::unique_ptr<HeadlessContext> shared;
        std::unique_ptr<CompileWorker> worker;   // modes worker/binary: the compile thread; warm: the loader
        std::unique_ptr<FolderWatcher> watcher;
        std::unique_ptr<LiveProgram> live;
        std::unique_ptr<FrameRenderer> fr;
        // adopt: programs drawn on the context that finished them; stage: by the thread that finished
        // them; render-process: by the process that finished them.
        std::unique_ptr<HandOverRun> handover;
        FrameInputs in;
        RenderPath path = RenderPath::Fragment;
        double steadyMedian = 0;
        int steadyMissed = 0;   // refreshes missed in the last 20 of the 30 steady frames
        std::vector<Round> rounds;
        std::vector<int> failedRounds;
        std::string note;
    };
    // The worker contexts live until the bench ends: on Mesa 22.3 llvmpipe, destroying a shared
    // context after the render context loaded program binaries (the program cache) crashed a later
    // draw on the render context (reproduced: warm cache, worker mode, then any mode). `live` keeps
    // its worker context for the whole session, so it never meets this. (Declared before the
    // modes, destroyed after their workers.)
    std::vector<std::unique_ptr<HeadlessContext>> workerContexts;
    std::vector<ModeRun> runs;
    auto bindMode = [](ModeRun& m) {   // the render thread's globals for this mode's builds
        PendingProgram::SetWorker(m.mode == 1 || m.mode == 2 ? m.worker.get() : nullptr);
        PendingProgram::SetLoader(m.mode == 4 ? m.worker.get() : nullptr);
    };
    struct Unset {
        ~Unset() {
            PendingProgram::SetWorker(nullptr);
            PendingProgram::SetLoader(nullptr);
        }
    } unset;
    std::stringstream modeList(o.modes);
    std::string modeName;
    bool workerMeasured = false;
    while (std::getline(modeList, modeName, ',')) {
        // render-process+NAME=VALUE[+NAME=VALUE..]: render-process with these in its servers' environment
        std::vector<std::string> serverEnv;
        std::string shownName = modeName;
        // MODE-evaluator: the mode with LiveProgram's evaluator tier on (a save drawn by the built
        // evaluator program with the save's code, no build; live_program_eval.cpp).
        const bool evaluator = modeName.size() > 10 && modeName.compare(modeName.size() - 10, 10, "-evaluator") == 0;
        if (evaluator) modeName.resize(modeName.size() - 10);
        if (modeName.rfind("render-process+", 0) == 0) {
            std::stringstream entries(modeName.substr(15));
            for (std::string e; std::getline(entries, e, '+');)
                if (e.find('=') != std::string::npos && e.find('=') > 0) serverEnv.push_back(e);
                else return Fail("--modes: '" + modeName + "': expected render-process+NAME=VALUE");
            modeName = "render-process";
        }
        if (const char* env = modeName == "render-process-one-image" ? "SDFVJ_SERVER_IMAGES=1" : modeName == "render-process-first-after-import" ? "SDFVJ_SERVER_PREPARE_IMAGES=0" : nullptr) serverEnv.push_back(env);   // the latter: as before session 41
        const bool inTurn = modeName == "render-process-in-turn";
        const bool importHere = modeName == "render-process-import-here";
        ImportOptions importOptions;
        importOptions.touch = modeName != "render-process-no-touch";
        importOptions.freeThere = modeName != "render-process-free-here";
        const bool atOnce = modeName == "render-process-at-once";   // both as before session 24
        importOptions.afterFrame = modeName != "render-process-import-now" && !atOnce;
        const bool reattach = modeName == "render-process-reattach";
        const bool retireNow = modeName == "render-process-retire-now" || atOnce;
        const bool standby = modeName == "render-process-standby";
        const bool firstAfterImport = modeName == "render-process-first-after-import";
        if (inTurn || importHere || reattach || retireNow || standby || firstAfterImport || !importOptions.touch || !importOptions.freeThere ||
            !importOptions.afterFrame)
            modeName = "render-process";
        int mode = modeName == "driver" ? 0 : modeName == "worker" ? 1 : modeName == "binary" ? 2 : modeName == "process" ? 3
                   : modeName == "warm" ? 4 : modeName == "adopt" ? 5 : modeName == "adopt-process" ? 6
                   : modeName == "process-source" ? 7 : modeName == "stage" ? 8 : modeName == "render-process" ? 9
                   : modeName == "render-process-shm" ? 10 : modeName == "render-process-sync" ? 11
                   : modeName == "render-process-one-image" ? 12 : -1;
        if (mode < 0)
            return Fail("--modes: '" + modeName + "', expected driver, worker, binary, process, process-source, warm, adopt, "
                        "adopt-process, stage, render-process, render-process-sync, render-process-one-image, render-process-in-turn, "
                        "render-process-import-here, render-process-no-touch, render-process-free-here, render-process-reattach, render-process-retire-now, render-process-import-now, render-process-at-once, render-process-standby, "
                        "render-process-first-after-import, render-process+NAME=VALUE or "
                        "render-process-shm");
        if (!post.empty() && mode < 9) return Fail("--post: render-process modes only (`bench post` times the chain in the show's process)");
        if (evaluator && mode >= 9) return Fail("--modes: '" + shownName + "': the evaluator tier is not in the render processes yet");
        ModeRun m;
        m.name = shownName;
        m.evaluator = evaluator;
        // process: `sdfvj compile-server` compiles, the render thread loads its binary. warm: the
        // same, but a loader thread (shared context) loads the binary and uses it once before the
        // hand-over. A driver without binaries cannot serve either: measured as the fallback.
        // process-source: the same server, but its reply only says the program is built, and the
        // render thread compiles the same text for the drivers' disk caches to serve.
        if (mode == 3 || mode == 4 || mode == 6 || mode == 7 || mode == 8) {
            m.process = std::make_unique<CompileProcess>();
            if (!m.process->Start(&error)) {
                m.note = "compile process: " + error + ": measured in-process instead";
                m.process.reset();
            }
            if (m.process) m.process->SetHandOverSource(mode == 7);
        }
        if (mode == 2 && binaryFormats == 0) {
            // A mode the driver cannot serve falls back instead of failing the bench.
            std::printf("\nbinary hand-over: the driver gives no program binaries (GL_NUM_PROGRAM_BINARY_FORMATS 0; "
                        "Mesa gives them only with its disk cache on): %s\n",
                        workerMeasured ? "same as the shared-context worker, not repeated"
                                       : "measured as the shared-context worker instead");
            if (workerMeasured) continue;
            mode = 1;
        }
        m.mode = mode;
        workerMeasured = workerMeasured || mode == 1;
        if (mode == 1 || mode == 2 || mode == 4) {
            workerContexts.push_back(std::make_unique<HeadlessContext>());
            HeadlessContext& shared = *workerContexts.back();
            if (!shared.CreateShared(gl, &error, mode != 2)) return Fail(error);
            m.worker = std::make_unique<CompileWorker>([&shared] { return shared.MakeCurrent(); }, mode == 2,
                                                       [&shared] { shared.ReleaseCurrent(); });
            if (!m.worker->Ok()) return Fail("the worker's context failed");
        }
        bindMode(m);
        m.watcher = std::make_unique<FolderWatcher>();
        for (const char* d : {"shaders/lib", "shaders/scenes", "shaders/render", "shaders/isf"}) m.watcher->Watch((root / d).string(), &error);
        m.path = o.path == "compute" ? RenderPath::Compute : o.path == "fragment" ? RenderPath::Fragment
                                                                                  : ProbeRenderPath(scene, nullptr);
        // Each entry of --modes its own programs (by its place, not its mode: render-process+NAME=VALUE
        // shares render-process's number, and a program cache would serve it the other's builds).
        m.entry = (int)runs.size() + 1;
        save(100 * m.entry);   // this mode's starting program: new as well
        m.watcher->Poll();
        m.live = std::make_unique<LiveProgram>();
        if (o.tiered != "auto") m.live->SetTiered(o.tiered == "on");
        m.live->SetCompileProcess(mode == 6 ? nullptr : m.process.get());   // only the process modes use one
        m.live->SetLiteralTier(retune);
        m.live->Request(VariantKey{sceneFile.string(), scene.effects, m.path});
        m.live->Wait();
        if (!m.live->Current()) return Fail(m.live->Error(), 1);
        // Built (and used once) before the steady frames, as it is between saves in `live`.
        m.live->SetEvaluatorTier(m.evaluator);
        if (m.evaluator && !m.live->WaitEvaluatorTier())
            m.note = "the evaluator tier could not be built: saves compile (" + m.live->EvaluatorError() + ")";
        else if (m.evaluator)
            m.note = "evaluator tier: its program compiled in " + std::to_string((int)m.live->EvaluatorBuildMs()) + " ms, used once in " +
                     std::to_string((int)m.live->EvaluatorPrimeMs()) + " ms; the scene translated in " +
                     std::to_string(m.live->EvaluatorTranslateMs()).substr(0, 5) + " ms";
        if (retune && !m.live->WaitLiteralTier()) m.note = "the literal tier could not be built: retunes compile";
        else if (retune)
            m.note = "literal tier: compiled in " + std::to_string((int)m.live->LiteralBuildMs()) + " ms, its one use on the render thread " +
                     std::to_string((int)m.live->LiteralPrimeMs()) + " ms (in `live` a frame that long after each structural save)";
        m.fr = std::make_unique<FrameRenderer>();
        if (!m.fr->Resize(w, h, &error)) return Fail(error);
        if (mode == 5 || mode == 6) m.handover = std::make_unique<AdoptRun>(m.process.get());
        if (mode == 8) m.handover = std::make_unique<StageRun>(m.process.get());
        if (mode >= 9)
            m.handover = std::make_unique<RenderProcessRun>(mode == 10 ? FrameTransport::Shm : FrameTransport::VkMemory, mode != 11,
                                                            m.live->Tiered(), serverEnv, inTurn, !importHere, importOptions);
        if (mode >= 9) {
            auto* run = static_cast<RenderProcessRun*>(m.handover.get());
            run->SetReattach(reattach);
            run->Show().SetRetireAtOnce(retireNow);
            run->Show().SetStandby(standby);
            run->Show().SetFirstFrameAfterImport(firstAfterImport);
            m.standby = standby;
            run->SetPost(post);
        }
        if (m.handover) {
            if (!m.handover->Start(gl, sceneFile.string(), m.path, w, h, &error)) return Fail(error);
            gl.MakeCurrent();
        }
        for (const ParamDecl& d : scene.params) m.in.params.emplace_back(d.name, d.defaultValue);
        runs.push_back(std::move(m));
    }

    // One frame as `live` runs it: the reload step, the draw, the pixels done; then paced.
    double updateMs = 0;
    int missed = 0;   // refreshes a paced display showed the frame before again (RefreshesMissed)
    std::string adoptError;
    auto frameOnce = [&](ModeRun& m, bool* swapped) {
        const auto t0 = Clock::now();
        if (m.handover) {
            *swapped = m.handover->Update(m.watcher->Poll(), sceneFile.string(), m.path, &adoptError);
            updateMs = MsSince(t0);
            m.handover->Draw(m.in);
        } else {
            *swapped = m.live->Update(m.watcher->Poll());
            updateMs = MsSince(t0);
            m.fr->Draw(*m.live->Current(), m.live->Scene(), m.in);
        }
        glFinish();
        if (m.handover) m.handover->FrameDone();
        const double ms = MsSince(t0);
        missed += RefreshesMissed(ms, o.fps);
        PaceFrame(ms, o.fps);
        return ms;
    };
    for (ModeRun& m : runs) {
        bindMode(m);
        std::vector<double> steady;
        bool swapped = false;
        // 2 s first: the programs' first use, and a render-process mode's spares starting (contexts,
        // warm-up builds) on the cores these frames need, are not the steady show between saves.
        for (const auto t0 = Clock::now(); MsSince(t0) < 2000;) frameOnce(m, &swapped);
        const int missedBefore = missed;
        for (int i = 0; i < 30; ++i) steady.push_back(frameOnce(m, &swapped));
        m.steadyMedian = MedianMs(steady);
        m.steadyMissed = missed - missedBefore;
    }

    auto runRound = [&](ModeRun& m, int round) {
        if (m.standby) {   // its spare holds the program on screen ready before the save, as in a show between saves
            bool ignored = false;
            auto& show = static_cast<RenderProcessRun*>(m.handover.get())->Show();
            for (const auto t0 = Clock::now(); !show.StandbyReady() && MsSince(t0) < 60000;) frameOnce(m, &ignored);
        }
        Round r;
        LiveProgram& live = *m.live;
        bool swapped = false;
        if (!post.empty()) postSaves.Save(100 * m.entry + round);
        else SaveLikeAnEditor(sceneFile, nudged ? saveText(100 * m.entry + round) : original + "// round " + std::to_string(round) + "\n");
        const auto saved = Clock::now();
        const int missedBefore = missed;
        std::vector<double> recent;   // the last frames, for r.around
        while (MsSince(saved) < 120000) {
            const double ms = frameOnce(m, &swapped);
            ++r.frames;
            recent.push_back(ms);
            if (recent.size() > 4) recent.erase(recent.begin());
            if (ms > r.longestFrame) r.longestAt = MsSince(saved) - ms;
            r.longestFrame = std::max(r.longestFrame, ms);
            r.longestUpdate = std::max(r.longestUpdate, updateMs);
            if (m.handover) {
                const bool quick = m.handover->OnScreenQuick();
                if (swapped && r.firstMs == 0) {
                    r.firstMs = MsSince(saved);
                    r.firstDraw = ms - updateMs;
                }
                if (quick && r.firstMs > 0) r.quickFrames.push_back(ms);
                r.quickSeen = r.quickSeen || quick;
                if (!swapped || quick) {
                    if (r.firstMs == 0) r.longestBefore = std::max(r.longestBefore, ms);
                    if (!adoptError.empty()) break;
                    continue;
                }
                r.optimizedMs = MsSince(saved);
                r.compileMs = m.handover->LastBuildMs();
                r.usedBefore = true;   // used once on its context before it went on screen
                r.ok = true;
                break;
            }
            if (!swapped) {
                if (r.firstMs == 0) r.longestBefore = std::max(r.longestBefore, ms);
                if (r.firstMs > 0 && live.Current()->QuickTier()) r.quickFrames.push_back(ms);
                if (!live.Error().empty() && !live.Pending()) break;
                continue;
            }
            if (r.firstMs == 0) {
                r.firstMs = MsSince(saved);
                r.firstDraw = ms - updateMs;
            }
            r.quickSeen = r.quickSeen || live.Current()->QuickTier();
            r.evaluatorSeen = r.evaluatorSeen || live.Current()->Origin().evaluatorTier;
            r.usedBefore = r.usedBefore || live.Current()->Origin().usedBeforeHandOver;
            r.loadMs = std::max(r.loadMs, live.Current()->Origin().loadMs);
            if (live.Current()->QuickTier()) r.quickFrames.push_back(ms);
            if (!live.Current()->QuickTier()) {
                r.optimizedMs = MsSince(saved);
                r.compileMs = live.Current()->Origin().buildMs;
                r.fromCache = live.Current()->FromCache();
                r.beginCall = live.Current()->Origin().beginCallMs;
                r.finishCall = live.Current()->Origin().finishCallMs;
                r.ok = true;
                break;
            }
        }
        if (r.ok) {   // the frames after the swap, while what it replaced is retired (counted apart)
            r.around = recent;
            r.around.insert(r.around.begin(), 4 - recent.size(), 0.0);
            const auto swapAt = Clock::now();
            for (int i = 0; MsSince(swapAt) < 300; ++i) {
                const double ms = frameOnce(m, &swapped);
                if (i < 3) r.around.push_back(ms);
                r.longestAfter = std::max(r.longestAfter, ms);
            }
        }
        r.missed = missed - missedBefore;
        // A round that timed out leaves no build behind for the next mode's globals.
        if (live.Pending()) live.Wait();
        return r;
    };
    if (o.driverCache == "warm")
        for (int round = 1; round <= o.rounds; ++round)
            for (ModeRun& m : runs) {   // untimed: fills the caches
                bindMode(m);
                runRound(m, round);
            }
    for (int round = 1; round <= o.rounds; ++round)
        for (ModeRun& m : runs) {
            bindMode(m);
            Round r = runRound(m, round);
            if (r.ok) m.rounds.push_back(r);
            else m.failedRounds.push_back(round);
        }

    std::vector<ReloadSummary> summary;
    for (ModeRun& m : runs) {
        LiveProgram& live = *m.live;
        const char* how = ReloadModeHow(m.mode, m.process != nullptr);
        if (!m.note.empty()) std::printf("\n%s\n", m.note.c_str());
        char evaluated[160] = "";
        if (live.EvaluatorSwaps() > 0)
            std::snprintf(evaluated, sizeof evaluated, "; evaluator tier: %d saves drawn with no build (the last translated in %.1f ms)",
                          live.EvaluatorSwaps(), live.EvaluatorTranslateMs());
        std::printf("\n## %s: %s, %s path, compile %s; tiered: %s%s%s\n", m.name.c_str(), scene.name.c_str(), RenderPathName(m.path),
                    how, live.Tiered() ? "yes (quick tier first)" : "no",
                    live.LiteralTierReady() ? "; literal tier: yes (a retune is drawn from uniforms at once)" : "", evaluated);
        std::printf("| round | first tier on screen ms | optimized on screen ms | frames | longest frame ms | "
                    "longest reload step ms (Begin / Finish calls) | first draw of new program ms | frame ms on the quick tier (or the evaluator) | "
                    "compile ms (its own) | used before the hand-over (load + first use ms) | from program cache |\n"
                    "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n");
        for (int round : m.failedRounds)
            std::printf("| %d | no new program on screen: %s |\n", round,
                        !adoptError.empty() && m.handover ? adoptError.c_str()
                        : live.Error().empty()         ? "timed out after 120 s"
                                                       : live.Error().c_str());
        for (size_t i = 0; i < m.rounds.size(); ++i) PrintReloadRound((int)i + 1, m.rounds[i]);
        if (m.rounds.empty()) return Fail("no round put a new program on screen (" + m.name + ")", 1);
        const ReloadSummary sum = ReportReloadRounds(m.name, m.rounds, m.steadyMedian, m.steadyMissed, o.fps);
        if (m.handover && !m.handover->Details().empty()) std::printf("%s\n", m.handover->Details().c_str());
        summary.push_back(sum);
    }
    if (o.driverCache == "fresh") std::printf("%s", DriverCacheContents(root / "driver-cache").c_str());
    PrintModesSideBySide(summary, o.fps);
    return 0;
}

}  // namespace sdfvj
