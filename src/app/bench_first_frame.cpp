#include "app/bench_first_frame.h"

#include <epoxy/gl.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <thread>

#include "app/bench_support.h"
#include "render/compile_worker.h"
#include "render/live_program.h"
#include "render/program_cache.h"

namespace sdfvj {

int ReloadBenchFail(const std::string& what, int code) {
    std::fprintf(stderr, "sdfvj bench reload: %s\n", what.c_str());
    return code;
}

const char* ReloadModeHow(int mode, bool process) {
    if (mode >= 9)
        return "in a render process of its own (sdfvj render-server, started ahead as a spare), which compiles, uses "
               "and draws it while the one on screen draws; every frame then drawn there and handed over "
               "(compile column: its compile + link, first use and first frame)";
    if (mode == 8 && !process)
        return "on a new stage's thread (its own shared context), which draws its first frame there while the "
               "stage on screen draws; every frame then drawn by that stage's thread, presented here (stage, "
               "no compile process: the driver gives no binaries)";
    if (mode == 8)
        return "in a compile process, its binary loaded, used once and drawn by a new stage (a thread with a shared context) "
               "while the stage on screen draws; every frame then drawn by that stage's thread, presented here (stage; "
               "compile column: the new stage's load + first use + first frame)";
    if (mode == 7)
        return process ? "in a compile process, then again from the same text on the render thread for the driver's disk cache to serve (process-source)"
                       : "by the driver (the compile process did not start)";
    if (mode == 6 && process)
        return "in a compile process, its binary loaded and used on a new shared context per save, the program then drawn on that context (adopt-process)";
    if (mode >= 5) return "on a new shared context per save, the program then drawn on that context (adopt)";
    if (process && mode == 4)
        return "in a compile process (sdfvj compile-server); a loader thread loads its binary and uses it once before the hand-over";
    if (process) return "in a compile process (sdfvj compile-server), handing over a program binary";
    if (mode == 2) return "on a worker thread with its own context, handing over a program binary";
    if (mode == 1) return "on a worker thread with a shared context";
    return PendingProgram::ParallelCompileAvailable() ? "by the driver (GL_KHR_parallel_shader_compile)" : "on the render thread";
}

namespace {

// SDFVJ_GL_DEBUG=1: the driver's debug messages (recompiles "based on GL state", say) to stderr.
void GLAPIENTRY PrintGlMessage(GLenum, GLenum type, GLuint, GLenum severity, GLsizei, const GLchar* message, const void*) {
    std::fprintf(stderr, "GL debug (type 0x%x, severity 0x%x): %s\n", type, severity, message);
}

}  // namespace

int ReloadFirstFrame(const ReloadBenchOptions& o, const SceneInfo& scene, int w, int h, const std::string& cacheLine) {
    const auto start = Clock::now();
    HeadlessContext gl;
    std::string error;
    if (!gl.Create(&error)) return ReloadBenchFail(error);
    const double contextMs = MsSince(start);
    const auto opened = Clock::now();
    if (const char* dbg = std::getenv("SDFVJ_GL_DEBUG"); dbg && std::string(dbg) == "1") {
        glEnable(GL_DEBUG_OUTPUT);
        glDebugMessageCallback(PrintGlMessage, nullptr);
    }
    RenderPath path = o.path == "compute" ? RenderPath::Compute : o.path == "fragment" ? RenderPath::Fragment
                                                                                      : ProbeRenderPath(scene, nullptr);
    // `--modes` naming warm: a loader thread (shared context) loads the cached binary and uses it
    // once before the first frame draws it, as `live` does where the compile process is used.
    std::unique_ptr<HeadlessContext> shared;
    std::unique_ptr<CompileWorker> loader;
    struct Unset { ~Unset() { PendingProgram::SetLoader(nullptr); } } unset;
    if (("," + o.modes + ",").find(",warm,") != std::string::npos) {
        shared = std::make_unique<HeadlessContext>();
        if (!shared->CreateShared(gl, &error, true)) return ReloadBenchFail(error);
        HeadlessContext* ctx = shared.get();
        loader = std::make_unique<CompileWorker>([ctx] { return ctx->MakeCurrent(); }, false, [ctx] { ctx->ReleaseCurrent(); });
        if (!loader->Ok()) return ReloadBenchFail("the loader's context failed");
        PendingProgram::SetLoader(loader.get());
    }
    LiveProgram live;
    if (o.tiered != "auto") live.SetTiered(o.tiered == "on");
    live.Request(VariantKey{scene.path, scene.effects, path});
    while (!live.Current() && live.Pending()) {
        live.Update({});
        if (!live.Current()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (!live.Current()) return ReloadBenchFail(live.Error(), 1);
    FrameRenderer fr;
    if (!fr.Resize(w, h, &error)) return ReloadBenchFail(error);
    FrameInputs in;
    for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
    // SDFVJ_BENCH_PRIME_HERE=1 (diagnosis): the loader's 1x1 priming use, on the render context,
    // timed on its own before the first real draw.
    double primeHereMs = -1;
    if (const char* here = std::getenv("SDFVJ_BENCH_PRIME_HERE"); here && std::string(here) == "1") {
        const auto t = Clock::now();
        PrimeProgram(live.Current()->Id(), path, false);
        primeHereMs = MsSince(t);
    }
    const auto drawAt = Clock::now();
    fr.Draw(*live.Current(), live.Scene(), in);
    glFinish();
    const double firstMs = MsSince(opened), drawMs = MsSince(drawAt);
    const Program& p = *live.Current();
    std::printf("# sdfvj bench reload --first-frame: %s at %dx%d, %s path, on %s\n", scene.name.c_str(), w, h,
                RenderPathName(path), gl.Description().c_str());
    std::printf("driver disk caches: %s; program cache: %s\n", cacheLine.c_str(),
                ProgramCacheEnabled() ? ProgramCacheFolder().c_str() : "off");
    std::printf("first frame %.1f ms after the context was made (context %.1f ms); program %s (%.1f ms); "
                "its first draw %.1f ms; %s\n", firstMs,
                contextMs, p.FromCache() ? "from the program cache" : p.QuickTier() ? "compiled, quick tier" : "compiled",
                p.Origin().buildMs, drawMs,
                p.Origin().usedBeforeHandOver ? ("loaded and used once on the loader thread first (" +
                                                  std::to_string((int)(p.Origin().loadMs + 0.5)) + " ms)").c_str()
                                              : "no loader");
    if (primeHereMs >= 0) std::printf("a 1x1 priming use on the render context before it: %.1f ms\n", primeHereMs);
    live.Wait();
    return 0;
}

}  // namespace sdfvj
