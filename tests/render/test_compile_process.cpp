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
#include "render/live_program.h"

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

TEST_CASE("compile process: LiveProgram reloads through it and no frame waits for the compile", "[compile_process]") {
    CompileProcess proc;
    if (!StartServer(&proc)) return;   // no binaries: nothing to hand over, the fallback is tested above
    const fs::path root = fs::temp_directory_path() / ("sdfvj-compile-process-live-" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root);
    fs::copy(fs::path(SDFVJ_SOURCE_ROOT) / "shaders", root / "shaders", fs::copy_options::recursive);
    setenv("SDFVJ_ROOT", root.c_str(), 1);
    const fs::path file = root / "shaders/scenes/midi.glsl";
    std::string original;
    {
        std::ifstream in(file);
        original.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const uint64_t nonce = (uint64_t)std::chrono::steady_clock::now().time_since_epoch().count();
    auto save = [&](int round) {   // a source no cache has seen, saved like an editor
        bool found = false;
        const std::string text = NudgeFirstConstant(original, 1e-6 * (double)(1 + (nonce + (uint64_t)round) % 1000), &found);
        REQUIRE(found);
        std::ofstream(file.string() + ".tmp~") << text;
        fs::rename(file.string() + ".tmp~", file);
    };
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
    unsetenv("SDFVJ_ROOT");
    fs::remove_all(root);
}

int main(int argc, char** argv) {
    if (argc == 2 && std::string(argv[1]) == "compile-server") return RunCompileServer(0, 1);
    setenv("SDFVJ_PROGRAM_CACHE", "0", 1);   // compiles only; the cache has its own tests
    return Catch::Session().run(argc, argv);
}
