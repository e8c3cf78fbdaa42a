// The compile process (render/compile_process.h) on llvmpipe: a program compiled in
// `compile-server` and handed over as a binary draws what an in-process build draws; a server that
// dies leaves the show to an in-process compile with nothing said; a broken shader's log comes back
// mapped to file:line. This binary is its own server (/proc/self/exe compile-server), as sdfvj is.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <epoxy/gl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "gl_fixture.h"
#include "render/compile_process.h"
#include "render/compile_worker.h"
#include "render/live_program.h"
#include "render/program_cache.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

ShaderSource Assemble(const SceneInfo& scene, RenderPath path) {
    ShaderSource src;
    std::string error;
    INFO(error);
    REQUIRE(AssembleProgram(scene, VariantKey{scene.path, scene.effects, path}, &src, &error));
    return src;
}

Image Draw(const Program& prog, const SceneInfo& scene) {
    FrameRenderer fr;
    std::string error;
    REQUIRE(fr.Resize(64, 48, &error));
    FrameInputs in;
    in.time = 1.0;
    for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
    fr.Draw(prog, scene, in);
    return Image{64, 48, fr.ReadPixels()};
}

// Polls like a frame loop would (Ready() never blocks), then finishes.
bool BuildThroughProcess(CompileProcess* proc, const ShaderSource& src, RenderPath path, Program* out, std::string* log,
                         int* polls = nullptr) {
    PendingProgram pending;
    pending.SetProcess(proc);
    pending.Begin(src, path);
    int n = 0;
    const auto t0 = std::chrono::steady_clock::now();
    while (!pending.Ready() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120)) {
        ++n;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (polls) *polls = n;
    return pending.Finish(out, log);
}

// Starts the server. Where the driver gives no program binaries (Mesa with
// MESA_SHADER_CACHE_DISABLE) Start() must refuse with the reason, and the caller checks the
// in-process fallback only.
bool StartServer(CompileProcess* proc) {
    RequireGl();
    GLint formats = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
    std::string error;
    const bool started = proc->Start(&error);
    INFO(error);
    if (formats == 0) {
        WARN("the driver gives no program binaries (Mesa's disk cache off): only the fallback is tested");
        CHECK_FALSE(started);
        CHECK(error.find("GL_NUM_PROGRAM_BINARY_FORMATS 0") != std::string::npos);
        CHECK_FALSE(proc->Usable());
        return false;
    }
    REQUIRE(started);
    return true;
}

// A copy of shaders/ in a temp folder (SDFVJ_ROOT) whose midi.glsl is saved like an editor saves,
// each save a source no cache has seen. Removed, and SDFVJ_ROOT unset, at the end.
struct ScratchScene {
    fs::path root, file;
    std::string original;
    uint64_t nonce = (uint64_t)std::chrono::steady_clock::now().time_since_epoch().count();
    explicit ScratchScene(const std::string& name) {
        root = fs::temp_directory_path() / ("sdfvj-compile-process-" + name + "-" + std::to_string(::getpid()));
        fs::remove_all(root);
        fs::create_directories(root);
        fs::copy(fs::path(SDFVJ_SOURCE_ROOT) / "shaders", root / "shaders", fs::copy_options::recursive);
        setenv("SDFVJ_ROOT", root.c_str(), 1);
        file = root / "shaders/scenes/midi.glsl";
        std::ifstream in(file);
        original.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    ~ScratchScene() {
        unsetenv("SDFVJ_ROOT");
        std::error_code ec;
        fs::remove_all(root, ec);
    }
    void Save(int round) {
        bool found = false;
        const std::string text = NudgeFirstConstant(original, 1e-9 * (double)(1 + (nonce + (uint64_t)round) % 999999), &found);
        REQUIRE(found);
        std::ofstream(file.string() + ".tmp~") << text;
        fs::rename(file.string() + ".tmp~", file);
    }
};

double MsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// The loader (PendingProgram::SetLoader): a CompileWorker on a context that shares objects with
// the test's. It lives until main() ends: on Mesa 22.3 a draw on the main context crashed after a
// shared context that had loaded program binaries went away.
std::unique_ptr<HeadlessContext> g_loaderContext;
std::unique_ptr<CompileWorker> g_loader;
CompileWorker* TestLoader() {
    if (!g_loader) {
        RequireGl();
        g_loaderContext = std::make_unique<HeadlessContext>();
        std::string error;
        INFO(error);
        REQUIRE(g_loaderContext->CreateShared(*TestContext(), &error, true));
        HeadlessContext* ctx = g_loaderContext.get();
        g_loader = std::make_unique<CompileWorker>([ctx] { return ctx->MakeCurrent(); }, false, [ctx] { ctx->ReleaseCurrent(); });
        REQUIRE(g_loader->Ok());
    }
    return g_loader.get();
}
struct LoaderOn {
    LoaderOn() { PendingProgram::SetLoader(TestLoader()); }
    ~LoaderOn() { PendingProgram::SetLoader(nullptr); }
};

}  // namespace

TEST_CASE("compile process: its binary draws the same image as an in-process build", "[compile_process]") {
    CompileProcess proc;
    const bool served = StartServer(&proc);
    for (const char* name : {"midi", "primitives"}) {
        SceneInfo scene;
        std::string error;
        REQUIRE(FindScene(name, &scene, &error));
        const ShaderSource src = Assemble(scene, RenderPath::Fragment);
        Program here, there;
        INFO(name << ": " << error);
        int polls = 0;
        REQUIRE(BuildThroughProcess(&proc, src, RenderPath::Fragment, &there, &error, &polls));
        REQUIRE(here.Build(src, RenderPath::Fragment, &error));
        CHECK(there.Origin().fromProcess == served);
        // (Ready() may say "done" at once: Mesa's disk cache can serve the server from an earlier run.)
        const ImageDiff d = CompareImages(Draw(here, scene), Draw(there, scene), 1);
        INFO("max channel difference " << d.maxAbs << ", mean " << d.meanAbs);
        CHECK(d.maxAbs <= 1);   // within 1/255
    }
}

TEST_CASE("compile process: a killed server falls back to an in-process compile with no error", "[compile_process]") {
    CompileProcess proc;
    const bool served = StartServer(&proc);
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    const ShaderSource src = Assemble(scene, RenderPath::Fragment);
    Program reference;
    REQUIRE(reference.Build(src, RenderPath::Fragment, &error));
    const Image want = Draw(reference, scene);

    // Killed while a job is queued or compiling: that job comes back from an in-process compile.
    PendingProgram pending;
    pending.SetProcess(&proc);
    pending.Begin(src, RenderPath::Fragment);
    if (served) REQUIRE(::kill(proc.Pid(), SIGKILL) == 0);
    Program first;
    std::string log;
    CHECK(pending.Finish(&first, &log));
    CHECK(log.empty());
    CHECK_FALSE(first.Origin().fromProcess);
    CHECK_FALSE(proc.Usable());
    CHECK(CompareImages(want, Draw(first, scene), 1).maxAbs <= 1);

    // Later builds go straight to the in-process path.
    Program second;
    CHECK(BuildThroughProcess(&proc, src, RenderPath::Fragment, &second, &log));
    CHECK(log.empty());
    CHECK_FALSE(second.Origin().fromProcess);
    CHECK(CompareImages(want, Draw(second, scene), 1).maxAbs <= 1);

    // A server that starts and exits at once (no GL there, say): the build restarts in-process.
    if (served) {
        CompileProcess quitter;
        REQUIRE(quitter.Start(&error, "/bin/true", {}));
        Program fourth;
        CHECK(BuildThroughProcess(&quitter, src, RenderPath::Fragment, &fourth, &log));
        CHECK(log.empty());
        CHECK_FALSE(fourth.Origin().fromProcess);
        CHECK(CompareImages(want, Draw(fourth, scene), 1).maxAbs <= 1);
    }

    // A server that never started (no such executable) is the same.
    CompileProcess missing;
    std::string why;
    CHECK_FALSE(missing.Start(&why, "/nonexistent/sdfvj", {"compile-server"}));
    if (served) CHECK(why.find("/nonexistent/sdfvj") != std::string::npos);
    Program third;
    CHECK(BuildThroughProcess(&missing, src, RenderPath::Fragment, &third, &log));
    CHECK(CompareImages(want, Draw(third, scene), 1).maxAbs <= 1);
}

TEST_CASE("compile process: a broken shader's log comes back with file:line", "[compile_process]") {
    CompileProcess proc;
    const bool served = StartServer(&proc);
    const fs::path root = fs::temp_directory_path() / ("sdfvj-compile-process-" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root);
    fs::copy(fs::path(SDFVJ_SOURCE_ROOT) / "shaders", root / "shaders", fs::copy_options::recursive);
    const fs::path file = root / "shaders/scenes/brokenproc.glsl";
    std::ofstream(file) << "/*{ \"NAME\": \"brokenproc\" }*/\n"
                           "\n"
                           "vec4 map(vec3 p) {\n"
                           "    return vec4(1.0f, 0.0f, 0.0f, fBx(p));\n"
                           "}\n"
                           "float sceneLipschitz() { return 1.0f; }\n";
    setenv("SDFVJ_ROOT", root.c_str(), 1);
    SceneInfo scene;
    std::string error;
    const bool loaded = LoadScene(file.string(), &scene, &error);
    INFO(error);
    REQUIRE(loaded);
    const ShaderSource src = Assemble(scene, RenderPath::Fragment);
    Program prog;
    std::string log;
    CHECK_FALSE(BuildThroughProcess(&proc, src, RenderPath::Fragment, &prog, &log));
    INFO(log);
    CHECK(log.find("shaders/scenes/brokenproc.glsl:4:") != std::string::npos);
    CHECK_FALSE(prog.IsValid());
    CHECK(proc.Usable() == served);   // a broken shader is not a broken server
    unsetenv("SDFVJ_ROOT");
    fs::remove_all(root);
}

TEST_CASE("compile process: LiveProgram reloads through it and no frame waits for the compile", "[compile_process][timed]") {
    CompileProcess proc;
    if (!StartServer(&proc)) return;   // no binaries: nothing to hand over, the fallback is tested above
    ScratchScene scratch("live");
    const fs::path& file = scratch.file;
    auto save = [&](int round) { scratch.Save(round); };
    save(0);
    LiveProgram live;
    live.SetCompileProcess(&proc);
    live.SetTiered(false);
    const VariantKey key{file.string(), EffectSet{}, RenderPath::Fragment};
    live.Request(key);
    live.Wait();
    INFO(live.Error());
    REQUIRE(live.Current() != nullptr);
    CHECK(live.Current()->Origin().fromProcess);
    FrameRenderer fr;
    std::string error;
    REQUIRE(fr.Resize(64, 48, &error));
    std::vector<double> ratios;
    for (int round = 1; round <= 3; ++round) {
        save(round);
        const Program* before = live.Current();
        double longest = 0;
        const auto saved = std::chrono::steady_clock::now();
        bool swapped = false;
        while (!swapped && std::chrono::steady_clock::now() - saved < std::chrono::seconds(120)) {
            const auto t0 = std::chrono::steady_clock::now();
            swapped = live.Update({file.string()}) && live.Current() != before;
            FrameInputs in;
            fr.Draw(*live.Current(), live.Scene(), in);
            glFinish();
            longest = std::max(longest, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        INFO("round " << round << ": " << live.Error());
        REQUIRE(swapped);
        CHECK(live.Current()->Origin().fromProcess);
        const double compile = live.Current()->Origin().buildMs;
        INFO("longest frame " << longest << " ms, compile " << compile << " ms");
        ratios.push_back(longest / std::max(compile, 1.0));
    }
    std::sort(ratios.begin(), ratios.end());
    INFO("longest frame / compile, per save (sorted): " << ratios[0] << " " << ratios[1] << " " << ratios[2]);
    CHECK(ratios[1] < 0.25);   // the median: a frame never waits for the compile
}

TEST_CASE("compile process: with a loader each binary is used once off the render thread and frames never wait for it", "[compile_process][loader][timed]") {
    CompileProcess proc;
    if (!StartServer(&proc)) return;   // no binaries: nothing to load
    LoaderOn loaderOn;
    ScratchScene scratch("loader");
    scratch.Save(0);
    LiveProgram live;
    live.SetCompileProcess(&proc);
    live.SetTiered(false);
    live.Request(VariantKey{scratch.file.string(), EffectSet{}, RenderPath::Fragment});
    live.Wait();
    INFO(live.Error());
    REQUIRE(live.Current() != nullptr);
    CHECK(live.Current()->Origin().fromProcess);
    CHECK(live.Current()->Origin().usedBeforeHandOver);
    {   // the program that went through the loader draws what an in-process build draws
        Program here;
        std::string error;
        REQUIRE(here.Build(live.Current()->Source(), RenderPath::Fragment, &error));
        const ImageDiff d = CompareImages(Draw(here, live.Scene()), Draw(*live.Current(), live.Scene()), 1);
        INFO("max channel difference " << d.maxAbs);
        CHECK(d.maxAbs <= 1);
    }
    // Each save: the loader is first kept busy with a compile of another scene (its own, new
    // source), so the binary's load waits behind it. A render thread that waited for the loader
    // would show a frame as long as that job; frames keep their cadence instead.
    SceneInfo busyScene;
    std::string error;
    REQUIRE(FindScene("character", &busyScene, &error));
    const ShaderSource busySrc = Assemble(busyScene, RenderPath::Fragment);
    FrameRenderer fr;
    REQUIRE(fr.Resize(64, 48, &error));
    std::vector<double> ratios, finishCalls, loads;
    int queuedBehind = 0;
    for (int round = 1; round <= 3; ++round) {
        bool found = false;
        const std::string busyText = NudgeFirstConstant(busySrc.text, 1e-9 * (double)(1 + (scratch.nonce + 17u * round) % 999999), &found);
        REQUIRE(found);
        const uint64_t busy = g_loader->Submit(busyText, RenderPath::Fragment);
        scratch.Save(round);
        const Program* before = live.Current();
        const auto saved = std::chrono::steady_clock::now();
        double longest = 0, busyMs = 0, busyDoneAt = -1, swapAt = -1;
        while (swapAt < 0 && MsSince(saved) < 120000) {
            const auto t0 = std::chrono::steady_clock::now();
            if (live.Update({scratch.file.string()}) && live.Current() != before) swapAt = MsSince(saved);
            FrameInputs in;
            fr.Draw(*live.Current(), live.Scene(), in);
            glFinish();
            longest = std::max(longest, MsSince(t0));
            CompileWorker::Result r;
            if (busyDoneAt < 0 && g_loader->Poll(busy, &r)) {
                busyDoneAt = MsSince(saved);
                busyMs = r.buildMs;
                if (r.program) glDeleteProgram(r.program);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        INFO("round " << round << ": " << live.Error());
        REQUIRE(swapAt >= 0);
        const ProgramOrigin& o = live.Current()->Origin();
        CHECK(o.fromProcess);
        CHECK(o.usedBeforeHandOver);   // it ran once on the loader before the render thread had it
        CHECK(o.loadMs > 0);
        while (busyDoneAt < 0) {   // the busy job ends (it was queued before the load)
            CompileWorker::Result r;
            if (g_loader->Poll(busy, &r)) {
                busyDoneAt = MsSince(saved);
                busyMs = r.buildMs;
                if (r.program) glDeleteProgram(r.program);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        CHECK(busyDoneAt <= swapAt + 50);   // one job at a time, in order: the load came after it
        if (o.buildMs < busyMs) ++queuedBehind;   // the server's binary was in before the loader was free
        INFO("longest frame " << longest << " ms; loader busy " << busyMs << " ms; save -> screen " << swapAt
                              << " ms; Finish on the render thread " << o.finishCallMs << " ms, load + first use " << o.loadMs << " ms");
        ratios.push_back(longest / std::max(busyMs, 1.0));
        finishCalls.push_back(o.finishCallMs);
        loads.push_back(o.loadMs);
    }
    std::sort(ratios.begin(), ratios.end());
    INFO("longest frame / loader busy, per save (sorted): " << ratios[0] << " " << ratios[1] << " " << ratios[2]
         << "; saves whose binary waited for the loader: " << queuedBehind);
    CHECK(ratios[1] < 0.25);   // the median: no frame waited for the loader
    // The render thread's part of the hand-over (adopting the program) is less than the load and
    // first use the loader did for it (median over the saves).
    CHECK(MedianMs(finishCalls) < MedianMs(loads));
}

TEST_CASE("compile process: with a loader a cached program is used once first, and one the driver refuses is compiled over", "[compile_process][loader][cache]") {
    RequireGl();
    GLint formats = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
    if (formats == 0) {
        WARN("the driver gives no program binaries (Mesa's disk cache off): nothing is cached to load");
        return;
    }
    LoaderOn loaderOn;
    const fs::path folder = fs::temp_directory_path() / ("sdfvj-compile-process-cache-" + std::to_string(::getpid()));
    fs::remove_all(folder);
    setenv("XDG_CACHE_HOME", folder.c_str(), 1);
    setenv("SDFVJ_PROGRAM_CACHE", "1", 1);
    struct Restore {
        fs::path folder;
        ~Restore() {
            setenv("SDFVJ_PROGRAM_CACHE", "0", 1);
            unsetenv("XDG_CACHE_HOME");
            std::error_code ec;
            fs::remove_all(folder, ec);
        }
    } restore{folder};
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("mandelbulb", &scene, &error));
    const ShaderSource src = Assemble(scene, RenderPath::Fragment);
    Program compiled;   // the first start compiles and stores it
    REQUIRE(compiled.Build(src, RenderPath::Fragment, &error));
    unsigned format = 0;
    std::vector<uint8_t> binary;
    REQUIRE(ReadCachedBinary(src.text, RenderPath::Fragment, &format, &binary));
    const Image want = Draw(compiled, scene);

    auto startFromCache = [&](Program* into, std::string* log) {
        PendingProgram pending;
        REQUIRE(pending.BeginFromCache(src, RenderPath::Fragment));
        const auto t0 = std::chrono::steady_clock::now();
        while (!pending.Ready() && MsSince(t0) < 120000) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        return pending.Finish(into, log);
    };
    Program second;   // a second start: from the cache, through the loader
    std::string log;
    REQUIRE(startFromCache(&second, &log));
    CHECK(second.FromCache());
    CHECK(second.Origin().usedBeforeHandOver);
    CHECK(CompareImages(want, Draw(second, scene), 1).maxAbs <= 1);

    // A file that passes every check of ours but holds a binary the driver refuses (a driver
    // update under the same version string, say): compiled over, nothing said, stored anew.
    const std::vector<uint8_t> refused(binary.size(), 0x5a);
    REQUIRE(StoreCachedBinary(format, refused, src.text, RenderPath::Fragment));
    Program third;
    CHECK(startFromCache(&third, &log));
    CHECK(log.empty());
    CHECK_FALSE(third.FromCache());
    CHECK_FALSE(third.Origin().usedBeforeHandOver);
    CHECK(CompareImages(want, Draw(third, scene), 1).maxAbs <= 1);
    std::vector<uint8_t> now;
    CHECK(ReadCachedBinary(src.text, RenderPath::Fragment, &format, &now));
    CHECK(now != refused);
}

int main(int argc, char** argv) {
    if (argc == 2 && std::string(argv[1]) == "compile-server") return RunCompileServer(0, 1);
    setenv("SDFVJ_PROGRAM_CACHE", "0", 1);   // compiles only; the cache has its own tests
    const int failed = Catch::Session().run(argc, argv);
    g_loader.reset();          // the loader's thread ends, then its context goes
    g_loaderContext.reset();
    return failed;
}
