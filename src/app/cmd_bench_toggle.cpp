// `sdfvj bench reload --edit toggle`: an effect pad hit, timed. Each round asks for one of the six
// variants an effect pad reaches from the scene's own (OneEffectToggles: shadows, AO, specular,
// fog, PBR, one reflection), as `live` does, and times: hit -> the variant's image on screen,
// hit -> its optimized program, and the longest frame meanwhile. Three ways, rounds interleaved:
//   cold            nothing built ahead: the hit compiles (what live did before prefetching)
//   prefetch        live's prefetch (LiveProgram::Prefetch): the six built ahead into the variant
//                   cache before the hits
//   prefetch+prime  the same, each also used once on the render context when it arrives
//                   (SetPrimePrefetched: NVIDIA finishes a program at its first use per context)
// The prefetch ways also report how long building ahead took and its longest frame: what the
// audience sees while nothing is asked for. Driver disk caches as --driver-cache says (off by
// default) and the program cache off, so every way compiles every variant itself.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "app/bench_support.h"
#include "app/commands.h"
#include "render/live_program.h"

namespace sdfvj {

namespace {

struct Way {
    std::string name;
    bool prefetch = false, prime = false;
    std::unique_ptr<LiveProgram> live;
    std::unique_ptr<FrameRenderer> fr;
    FrameInputs in;
    double steadyMedian = 0, aheadMs = 0, aheadLongest = 0;
    std::vector<double> shown, optimized, longest;
    int failed = 0, hitCompiles = 0;   // compiles the hits started (built ahead: none)
};

}  // namespace

int RunToggleBench(const ReloadBenchOptions& o, const SceneInfo& scene, int w, int h, const std::string& cacheLine) {
    auto fail = [](const std::string& what) {
        std::fprintf(stderr, "sdfvj bench reload --edit toggle: %s\n", what.c_str());
        return 2;
    };
    setenv("SDFVJ_PROGRAM_CACHE", "0", 1);   // before the compile process starts: it inherits it
    std::string error;
    HeadlessContext gl;
    if (!gl.Create(&error)) return fail(error);
    const RenderPath path = o.path == "compute" ? RenderPath::Compute : o.path == "fragment" ? RenderPath::Fragment
                                                                                            : ProbeRenderPath(scene, nullptr);
    const VariantKey base{scene.path, scene.effects, path};
    std::vector<VariantKey> toggles;
    for (const EffectSet& e : OneEffectToggles(scene.effects)) toggles.push_back({scene.path, e, path});
    std::printf("# sdfvj bench reload --edit toggle: %s at %dx%d, %s path, on %s\n", scene.name.c_str(), w, h,
                RenderPathName(path), gl.Description().c_str());
    std::printf("driver disk caches: %s; program cache: off; frames paced at %s; %s\n", cacheLine.c_str(),
                o.fps > 0 ? (std::to_string((int)o.fps) + " Hz").c_str() : "flat out",
                LiveProgram::ProcessCompileDefault() ? "builds in the compile process (as live on this GPU)" : "builds in-process");

    const bool servers = o.modes.find("render-process") != std::string::npos;
    if (servers && o.modes == "render-process") return RunServerToggleWays(o, scene, path, toggles, w, h);
    std::vector<Way> ways(3);
    ways[0].name = "cold";
    ways[1].name = "prefetch";
    ways[1].prefetch = true;
    ways[2].name = "prefetch+prime";
    ways[2].prefetch = ways[2].prime = true;
    // One frame as live runs it: the reload step, the draw, the pixels done; then paced.
    auto frameOnce = [&](Way& m) {
        const auto t0 = Clock::now();
        m.live->Update({});
        m.fr->Draw(*m.live->Current(), m.live->Scene(), m.in);
        glFinish();
        const double ms = MsSince(t0);
        PaceFrame(ms, o.fps);
        return ms;
    };
    for (Way& m : ways) {
        m.live = std::make_unique<LiveProgram>();
        if (o.tiered != "auto") m.live->SetTiered(o.tiered == "on");
        m.live->SetCacheLimit(toggles.size() + 4);
        m.live->SetPrimePrefetched(m.prime);
        m.live->Request(base);
        m.live->Wait();
        if (!m.live->Current()) return fail(m.live->Error());
        m.fr = std::make_unique<FrameRenderer>();
        if (!m.fr->Resize(w, h, &error)) return fail(error);
        for (const ParamDecl& d : scene.params) m.in.params.emplace_back(d.name, d.defaultValue);
        WarmGpu([&] { frameOnce(m); });   // the clocks drop while the GPU waits on a compile
        std::vector<double> steady;
        for (int i = 0; i < 30; ++i) steady.push_back(frameOnce(m));
        m.steadyMedian = MedianMs(steady);
        if (!m.prefetch) continue;
        // Built ahead while frames keep coming, as in live once the show has been quiet a while.
        m.live->Prefetch(toggles);
        const auto t = Clock::now();
        while (m.live->PrefetchQueued() > 0 && MsSince(t) < 300000) m.aheadLongest = std::max(m.aheadLongest, frameOnce(m));
        m.aheadMs = MsSince(t);
    }
    const int rounds = std::min<int>(o.rounds, (int)toggles.size());
    for (int round = 0; round < rounds; ++round)
        for (Way& m : ways) {
            LiveProgram& live = *m.live;
            const Program* before = live.Current();
            const int compiles = live.CompilesStarted();
            const auto hit = Clock::now();
            live.Request(toggles[round]);
            double longest = 0, shown = -1;
            bool ok = false;
            while (MsSince(hit) < 120000) {
                const double ms = frameOnce(m);
                longest = std::max(longest, ms);
                if (shown < 0 && live.Current() != before) shown = MsSince(hit);
                if (shown >= 0 && !live.Current()->QuickTier()) {
                    ok = true;
                    break;
                }
                if (!live.Error().empty() && !live.Pending()) break;
            }
            m.hitCompiles += live.CompilesStarted() - compiles;
            if (ok) {
                m.shown.push_back(shown);
                m.optimized.push_back(MsSince(hit));
                m.longest.push_back(longest);
            } else {
                ++m.failed;
            }
            live.Request(base);   // back to the scene's own variant (cached: no compile), settled
            for (int i = 0; i < 10; ++i) frameOnce(m);
        }

    std::printf("\n| way | hit -> on screen (median) | hit -> optimized (median) | longest frame after a hit (max) | "
                "compiles the hits started | steady frame | building ahead: time, longest frame |\n|---|---:|---:|---:|---:|---:|---|\n");
    for (Way& m : ways) {
        const double worst = m.longest.empty() ? 0 : *std::max_element(m.longest.begin(), m.longest.end());
        char ahead[160] = "-";
        if (m.prefetch)
            std::snprintf(ahead, sizeof ahead, "%zu variants in %.0f ms, longest frame %.1f ms%s", toggles.size(), m.aheadMs,
                          m.aheadLongest, m.prime ? (" (its one use: " + std::to_string((int)m.live->PrefetchPrimeMs()) + " ms at most)").c_str() : "");
        std::printf("| %s | %.1f ms | %.1f ms | %.1f ms | %d | %.2f ms | %s |\n", m.name.c_str(),
                    m.shown.empty() ? 0 : MedianMs(m.shown), m.optimized.empty() ? 0 : MedianMs(m.optimized), worst,
                    m.hitCompiles, m.steadyMedian, ahead);
        if (m.failed) std::printf("  %s: %d of %d hits never reached the screen (%s)\n", m.name.c_str(), m.failed, rounds,
                                  m.live->Error().c_str());
    }
    for (Way& m : ways) m.live->Wait();
    return servers ? RunServerToggleWays(o, scene, path, toggles, w, h) : 0;
}

}  // namespace sdfvj
