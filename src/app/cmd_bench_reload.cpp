// `sdfvj bench reload`: how long a saved shader takes to reach the screen, and what the
// reload does to frame times. Works on a copy of shaders/ in a temp folder: each round appends a
// comment to the scene file (a real change of content, so a real recompile), then renders frames
// until the new program is on screen. Reports, per round: save -> first frame drawn with the
// new program, and the longest frame while the compile was pending.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>

#include "app/commands.h"
#include "render/compile_worker.h"
#include "render/live_program.h"
#include "shader/watch.h"

namespace fs = std::filesystem;

namespace sdfvj {

int RunReloadBench(const ReloadBenchOptions& o) {
    using Clock = std::chrono::steady_clock;
    std::string error;
    int w = 0, h = 0;
    if (!ParseSize(o.size, &w, &h, &error)) { std::fprintf(stderr, "sdfvj bench reload: %s\n", error.c_str()); return 2; }
    SceneInfo scene;
    if (!FindScene(o.scene, &scene, &error)) { std::fprintf(stderr, "sdfvj bench reload: %s\n", error.c_str()); return 2; }
    HeadlessContext gl;
    if (!gl.Create(&error)) { std::fprintf(stderr, "sdfvj bench reload: %s\n", error.c_str()); return 2; }

    const fs::path root = fs::temp_directory_path() / ("sdfvj-bench-reload-" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root);
    fs::copy(fs::path(DataRoot()) / "shaders", root / "shaders", fs::copy_options::recursive);
    const std::string oldRoot = DataRoot();
    setenv("SDFVJ_ROOT", root.c_str(), 1);
    const fs::path sceneFile = root / "shaders" / "scenes" / fs::path(scene.path).filename();

    // Three rounds of the same measurement: compiling through the driver on the render thread
    // (with GL_KHR_parallel_shader_compile where it exists), on a CompileWorker with a shared
    // context, and on a CompileWorker with its own context that hands over a program binary.
    for (int mode = 0; mode < 3; ++mode) {
    HeadlessContext shared;
    std::unique_ptr<CompileWorker> worker;
    if (mode >= 1) {
        if (!shared.CreateShared(gl, &error, mode == 1)) { std::fprintf(stderr, "sdfvj bench reload: %s\n", error.c_str()); break; }
        worker = std::make_unique<CompileWorker>([&shared] { return shared.MakeCurrent(); }, mode == 2,
                                                 [&shared] { shared.ReleaseCurrent(); });
        if (!worker->Ok()) { std::fprintf(stderr, "sdfvj bench reload: the worker's context failed\n"); break; }
        PendingProgram::SetWorker(worker.get());
    }
    FolderWatcher watcher;
    for (const char* d : {"shaders/lib", "shaders/scenes", "shaders/render"}) watcher.Watch((root / d).string(), &error);
    RenderPath path = o.path == "compute" ? RenderPath::Compute : o.path == "fragment" ? RenderPath::Fragment
                                                                                      : ProbeRenderPath(scene, nullptr);
    LiveProgram live;
    live.Request(VariantKey{sceneFile.string(), scene.effects, path});
    live.Wait();
    if (!live.Current()) { std::fprintf(stderr, "%s\n", live.Error().c_str()); return 1; }
    FrameRenderer fr;
    if (!fr.Resize(w, h, &error)) { std::fprintf(stderr, "sdfvj bench reload: %s\n", error.c_str()); return 2; }
    FrameInputs in;
    for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);

    auto frameOnce = [&](bool* swapped) {
        auto t0 = Clock::now();
        *swapped = live.Update(watcher.Poll());
        fr.Draw(*live.Current(), live.Scene(), in);
        glFinish();
        return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    };
    // Steady frames first: the frame time a reload should not disturb.
    std::vector<double> steady;
    bool swapped = false;
    for (int i = 0; i < 20; ++i) steady.push_back(frameOnce(&swapped));
    std::sort(steady.begin(), steady.end());

    std::printf("# sdfvj bench reload: %s at %dx%d, %s path, on %s; compile %s\n", scene.name.c_str(), w, h,
                RenderPathName(path), gl.Description().c_str(),
                mode == 2 ? "on a worker thread with its own context, handing over a program binary"
                : worker ? "on a worker thread with a shared context"
                       : (PendingProgram::ParallelCompileAvailable() ? "by the driver (GL_KHR_parallel_shader_compile)"
                                                                     : "on the render thread"));
    std::printf("| round | save -> new program on screen ms | frames meanwhile | longest frame ms |\n|---:|---:|---:|---:|\n");
    std::vector<double> latencies, longest;
    for (int round = 1; round <= o.rounds; ++round) {
        {
            std::ofstream f(sceneFile, std::ios::app);
            f << "// reload round " << round << "\n";
        }
        const auto saved = Clock::now();
        double worst = 0;
        int frames = 0;
        swapped = false;
        while (!swapped && std::chrono::duration<double>(Clock::now() - saved).count() < 60) {
            worst = std::max(worst, frameOnce(&swapped));
            ++frames;
        }
        const double latency = std::chrono::duration<double, std::milli>(Clock::now() - saved).count();
        latencies.push_back(latency);
        longest.push_back(worst);
        std::printf("| %d | %.1f | %d | %.1f |\n", round, latency, frames, worst);
    }
    std::sort(latencies.begin(), latencies.end());
    std::sort(longest.begin(), longest.end());
    std::printf("median: save -> screen %.1f ms, longest frame during a reload %.1f ms (steady frame median %.2f ms)\n",
                latencies[latencies.size() / 2], longest[longest.size() / 2], steady[steady.size() / 2]);
    PendingProgram::SetWorker(nullptr);
    }
    setenv("SDFVJ_ROOT", oldRoot.c_str(), 1);
    fs::remove_all(root);
    return 0;
}

}  // namespace sdfvj
