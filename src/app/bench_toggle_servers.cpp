// `bench reload --edit toggle --modes render-process`: effect pad hits as `live --render-process`
// takes them (issue 12). Two ways, rounds interleaved, each with a program cache folder of its own
// (the servers' environment, ServerShow::SetServerEnv), empty at the start:
//   render-process          each hit's variant is compiled, used and first drawn by its spare server
//   render-process, ahead   the variants were built ahead into the program cache by a server of their
//                           own (ServerShow::BuildAhead, as live does after a quiet while): each hit
//                           is a cache load in its spare
// The table: hit -> the variant's first frame on screen, the longest frame meanwhile, how many hits
// came from the cache, and what building ahead took.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <utility>

#include "app/bench_adopt.h"
#include "app/bench_support.h"
#include "app/commands.h"
#include "render/server_show.h"

namespace sdfvj {

namespace {

struct ServerWay {
    std::string name;
    bool ahead = false;
    std::unique_ptr<ServerShow> show;
    std::unique_ptr<PresentTarget> present;
    FrameInputs in;
    double steadyMedian = 0, aheadMs = 0, aheadLongest = 0;
    std::vector<double> shown, longest, buildMs, useMs;   // per hit; the last two in its server
    int failed = 0, fromCache = 0;
    std::string error;
};

}  // namespace

int RunServerToggleWays(const ReloadBenchOptions& o, const SceneInfo& scene, RenderPath path, const std::vector<VariantKey>& toggles,
                        int w, int h) {
    auto loadOf = [&](const EffectSet& e) { return ServerLoad{scene.path, false, e, path, w, h}; };
    const std::string folder = (std::filesystem::temp_directory_path() / ("sdfvj-toggle-" + std::to_string(::getpid()))).string();
    std::vector<ServerWay> ways(2);
    ways[0].name = "render-process";
    ways[1].name = "render-process, built ahead";
    ways[1].ahead = true;
    // One frame as live --render-process runs it: the servers polled, the frame drawn by the server on
    // screen and blitted here, the pixels done; then paced.
    auto frameOnce = [&](ServerWay& m, bool* changed = nullptr) {
        const auto t0 = Clock::now();
        std::string error;
        const bool c = m.show->Poll(&error);
        if (changed) *changed = c;
        if (!error.empty()) m.error = error;
        if (m.show->Frame(m.in, 5000)) m.present->Blit(m.show->Texture());
        glFinish();
        m.show->FrameDone();   // as live does after the swap
        const double ms = MsSince(t0);
        PaceFrame(ms, o.fps);
        return ms;
    };
    for (size_t i = 0; i < ways.size(); ++i) {
        ServerWay& m = ways[i];
        const std::string cache = folder + "/" + std::to_string(i);
        std::filesystem::create_directories(cache);
        m.show = std::make_unique<ServerShow>(FrameTransport::VkMemory, false, o.tiered == "on");
        std::vector<std::string> env = {"XDG_CACHE_HOME=" + cache, "SDFVJ_PROGRAM_CACHE=1"};
        for (const auto& [driver, sub] : {std::pair{"MESA_SHADER_CACHE_DIR", "mesa"}, std::pair{"__GL_SHADER_DISK_CACHE_PATH", "nv"}})
            if (std::getenv(driver)) {   // --driver-cache fresh: a folder each (NVIDIA writes only into one that exists)
                std::filesystem::create_directories(cache + "/" + sub);
                env.push_back(std::string(driver) + "=" + cache + "/" + sub);
            }
        m.show->SetServerEnv(env);
        std::string error;
        if (!m.show->Start(loadOf(scene.effects), &error)) {
            std::fprintf(stderr, "sdfvj bench reload --edit toggle: %s: %s\n", m.name.c_str(), error.c_str());
            return 2;
        }
        m.present = std::make_unique<PresentTarget>();
        m.present->Create(w, h);
        for (const ParamDecl& d : scene.params) m.in.params.emplace_back(d.name, d.defaultValue);
        WarmGpu([&] { frameOnce(m); });
        std::vector<double> steady;
        for (int k = 0; k < 30; ++k) steady.push_back(frameOnce(m));
        m.steadyMedian = MedianMs(steady);
        if (!m.ahead) continue;
        std::vector<ServerLoad> loads;
        for (const VariantKey& k : toggles) loads.push_back(loadOf(k.effects));
        m.show->BuildAhead(loads);
        const auto t = Clock::now();
        while (m.show->BuildAheadLeft() > 0 && MsSince(t) < 300000) m.aheadLongest = std::max(m.aheadLongest, frameOnce(m));
        m.aheadMs = MsSince(t);
    }
    // Frames until the program last loaded is on screen (its optimized one, when tiered); false after
    // 120 s or when it failed.
    auto untilShown = [&](ServerWay& m, Clock::time_point from, double* longest) {
        bool changed = false;
        while (MsSince(from) < 120000) {
            const double ms = frameOnce(m, &changed);
            if (longest) *longest = std::max(*longest, ms);
            if (changed && !m.show->OnScreenQuick()) return true;
            if (!m.error.empty() && !m.show->Building()) return false;
        }
        return false;
    };
    const int rounds = std::min<int>(o.rounds, (int)toggles.size());
    for (int round = 0; round < rounds; ++round)
        for (ServerWay& m : ways) {
            std::string error;
            m.error.clear();
            const auto hit = Clock::now();
            double longest = 0;
            if (m.show->Load(loadOf(toggles[round].effects), &error) && untilShown(m, hit, &longest)) {
                m.shown.push_back(MsSince(hit));
                m.longest.push_back(longest);
                const RenderProcess::Ready& r = m.show->Shown().back();
                m.fromCache += r.fromCache ? 1 : 0;
                m.buildMs.push_back(r.buildMs);
                m.useMs.push_back(r.useMs + r.firstFrameMs);
            } else {
                ++m.failed;
                if (m.error.empty()) m.error = error;
            }
            // Back to the scene's own variant (from the cache in both ways: the start stored it), settled.
            const std::string why = m.error;
            if (m.show->Load(loadOf(scene.effects), &error)) untilShown(m, Clock::now(), nullptr);
            m.error = why;
            for (int k = 0; k < 10; ++k) frameOnce(m);
        }

    std::printf("\n| way (live --render-process) | hit -> on screen (median) | in its server: build / first use + first frame (medians) | "
                "longest frame after a hit (max) | hits loaded from the program cache | steady frame | building ahead: time, longest frame |\n"
                "|---|---:|---:|---:|---:|---:|---|\n");
    for (ServerWay& m : ways) {
        const double worst = m.longest.empty() ? 0 : *std::max_element(m.longest.begin(), m.longest.end());
        char ahead[120] = "-";
        if (m.ahead) std::snprintf(ahead, sizeof ahead, "%zu variants in %.0f ms, longest frame %.1f ms", toggles.size(), m.aheadMs, m.aheadLongest);
        std::printf("| %s | %.1f ms | %.1f / %.1f ms | %.1f ms | %d of %zu | %.2f ms | %s |\n", m.name.c_str(), m.shown.empty() ? 0 : MedianMs(m.shown),
                    m.buildMs.empty() ? 0 : MedianMs(m.buildMs), m.useMs.empty() ? 0 : MedianMs(m.useMs), worst, m.fromCache, m.shown.size(),
                    m.steadyMedian, ahead);
        if (m.failed) std::printf("  %s: %d of %d hits never reached the screen (%s)\n", m.name.c_str(), m.failed, rounds, m.error.c_str());
    }
    for (size_t i = 0; i < ways.size(); ++i) {
        ways[i].present.reset();
        ways[i].show.reset();
        const std::string driver = DriverCacheContents(folder + "/" + std::to_string(i));
        if (!driver.empty()) std::printf("%s:%s", ways[i].name.c_str(), driver.c_str());
    }
    std::error_code ignored;
    std::filesystem::remove_all(folder, ignored);
    return 0;
}

}  // namespace sdfvj
