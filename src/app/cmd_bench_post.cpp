// `sdfvj bench post`: what a post effect's save costs the show's frames (issue 12), with the chain
// built in contexts of its own (IsfHost, as `live` builds it: drawn there on llvmpipe, by the render
// thread elsewhere; SDFVJ_POST_DRAW=own|render picks) against the chain built and drawn in the
// render thread's context (as before; `live` with SDFVJ_POST_CONTEXTS=0), and the first way with its
// first build's spare set of targets the other way (IsfHost::SetSpareTargets). Per effect and size:
//   steady   the chain's frame (IsfHost::Render + glFinish), the ways interleaved in blocks,
//            after the GPU has warmed; the first way timed again at the end (drift check)
//   saves    rounds of a save (the effect with a new function appended: a program no cache has
//            seen, the drivers' disk caches off), the ways interleaved: save -> the first frame
//            drawn by the new program, the longest frame in between (frames paced like a display),
//            and the frame that put the new chain on screen (the swap: adopt, delete the old chain);
//            each save's longest frame in order (the first save is the one the spare set is for), and
//            the first build's frame on screen
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "app/bench_support.h"
#include "app/commands.h"
#include "app/show.h"
#include "isf/isf_host.h"
#include "render/render.h"

namespace sdfvj {

namespace fs = std::filesystem;

namespace {

struct Way {
    std::string name;
    std::unique_ptr<IsfHost> host;
    std::string file, original;   // the copy its saves go to, and the effect as shipped
    std::vector<double> steady, toScreen, longest, swap, adopt, handover, draw, finish;
    double firstOn = 0.0, firstNext = 0.0;   // the first build: the frame that put it on screen, the longer of the next two
};

double lastFinishMs = 0.0;   // the last Frame's glFinish

// One frame: a finished build goes on screen, the chain draws over `input`, the GPU finishes.
double Frame(IsfHost& host, unsigned input, int w, int h, IsfFrameInputs& in, bool* adopted = nullptr, double* adoptMs = nullptr) {
    const auto t0 = Clock::now();
    IsfHost::Done done;
    if (host.Poll(&done) && adopted) *adopted = done.adopted;
    if (adoptMs) *adoptMs = done.adoptMs;
    ++in.frame;
    host.Render(input, w, h, in);
    const auto t1 = Clock::now();
    glFinish();
    lastFinishMs = MsSince(t1);
    return MsSince(t0);
}

}  // namespace

int RunPostBench(const PostBenchOptions& o) {
    const fs::path work = fs::temp_directory_path() / ("sdfvj-post-" + std::to_string(::getpid()));
    fs::create_directories(work);
    const std::string caches = SetDriverCaches("off", work, false);
    std::string error;
    int w = 0, h = 0;
    if (!ParseSize(o.size, &w, &h, &error)) {
        std::fprintf(stderr, "sdfvj bench post: %s\n", error.c_str());
        return 2;
    }
    HeadlessContext main, a, b, c, d;
    if (!main.Create(&error) || !a.CreateShared(main, &error, true) || !b.CreateShared(main, &error, true) ||
        !c.CreateShared(main, &error, true) || !d.CreateShared(main, &error, true) || !main.MakeCurrent()) {
        std::fprintf(stderr, "sdfvj bench post: %s\n", error.c_str());
        return 2;
    }
    const std::string gpu = (const char*)glGetString(GL_RENDERER);
    std::printf("# sdfvj bench post: %s on %s\ndrivers' disk caches %s; frames paced at %.0f fps during saves\n\n", o.size.c_str(),
                gpu.c_str(), caches.c_str(), o.fps);
    std::printf("| effect | size | chain drawn in | steady frame | save -> screen | longest frame in a save | longest / steady | the swap's frame | of it: adopt / hand-over / draw / finish |\n"
                "|---|---|---|---:|---:|---:|---:|---:|---|\n");
    // The raymarched frame's stand-in: an RGBA8 gradient (the format FrameRenderer draws into).
    unsigned input = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &input);
    glTextureStorage2D(input, 1, GL_RGBA8, w, h);
    std::vector<uint8_t> px((size_t)w * h * 4);
    for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t((i * 7 / 4) % 251);
    glTextureSubImage2D(input, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
    auto own = [](HeadlessContext& c) { return IsfHostContext{[&c] { return c.MakeCurrent(); }, [&c] { c.ReleaseCurrent(); }}; };
    BenchCsv csv;
    csv.extra = {"chain_in", "save_to_screen_ms", "longest_ms", "swap_frame_ms", "rounds"};
    std::vector<Drift> drifts;
    for (const std::string& listed : SplitIsfList(o.effects)) {
        const std::string path = ResolveIsfPath(listed), name = fs::path(path).stem().string();
        std::ifstream src(path, std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(src)), std::istreambuf_iterator<char>());
        if (text.empty()) {
            std::fprintf(stderr, "sdfvj bench post: cannot read %s\n", path.c_str());
            return 2;
        }
        // As `live` builds it (its own contexts, the spare set as the renderer's default), the same with the
        // spare set the other way (IsfHost::SetSpareTargets: a first save with and without it), and the window's context.
        constexpr int kWays = 3;
        Way ways[kWays] = {{"own contexts", std::make_unique<IsfHost>(std::array<IsfHostContext, 2>{own(a), own(b)})},
                           {"own contexts", std::make_unique<IsfHost>(std::array<IsfHostContext, 2>{own(c), own(d)})},
                           {"the window's context", std::make_unique<IsfHost>()}};
        ways[1].host->SetSpareTargets(!ways[0].host->SpareTargets());
        for (int k = 0; k < 2; ++k)   // built in contexts of its own, then drawn there or by the render thread (IsfDrawIn::Auto)
            ways[k].name = std::string(ways[k].host->DrawIn() == IsfDrawIn::OwnContexts ? "own contexts" : "built in own contexts, drawn here") +
                           (ways[k].host->SpareTargets() ? ", spare set" : ", no spare set");
        IsfFrameInputs in;
        for (int k = 0; k < kWays; ++k) {
            Way& way = ways[k];
            fs::create_directories(work / std::to_string(k));
            way.file = (work / std::to_string(k) / fs::path(path).filename()).string();
            way.original = text;
            std::ofstream(way.file, std::ios::binary) << text;
            IsfFile file;
            if (!LoadIsfFile(way.file, &file, &error)) {
                std::fprintf(stderr, "sdfvj bench post: %s\n", error.c_str());
                return 2;
            }
            way.host->Request({file}, w, h);
            bool adopted = false;
            for (const auto t0 = Clock::now(); !adopted && MsSince(t0) < 60000;) way.firstOn = Frame(*way.host, input, w, h, in, &adopted);
            way.firstNext = std::max(Frame(*way.host, input, w, h, in), Frame(*way.host, input, w, h, in));
            if (way.host->Chain().Empty()) {
                std::fprintf(stderr, "sdfvj bench post: %s did not build\n", path.c_str());
                return 2;
            }
        }
        WarmGpu([&] { for (Way& way : ways) Frame(*way.host, input, w, h, in); }, 1.0);
        auto steady = [&](Way& way) { return TimeMedian([&] { return Frame(*way.host, input, w, h, in); }, std::max(5, o.frames / 10)); };
        Drift drift{name + " " + SizeName(w, h) + " " + ways[0].name};
        drift.startMs = steady(ways[0]);
        for (int block = 0; block < 10; ++block)
            for (int k = 0; k < kWays; ++k) ways[(block + k) % kWays].steady.push_back(steady(ways[(block + k) % kWays]));
        // Saves, the ways interleaved (which goes first alternates).
        for (int round = 1; round <= o.rounds; ++round)
            for (int j = 0; j < kWays; ++j) {
                const int k = (round + j) % kWays;
                Way& way = ways[k];
                std::ofstream(way.file, std::ios::binary) << way.original << "\nfloat benchPostSave" << round << "_" << k << "() { return "
                                                          << round << ".0; }\n";
                std::vector<std::string> errors;
                const auto t0 = Clock::now();
                way.host->Reload(&errors);   // without contexts of its own, the build is in this call
                const double reloadMs = MsSince(t0);
                double longest = 0.0;
                bool adopted = false;
                for (int f = 0; !adopted && MsSince(t0) < 60000; ++f) {
                    double adoptMs = 0.0;
                    const double ms = Frame(*way.host, input, w, h, in, &adopted, &adoptMs) + (f == 0 ? reloadMs : 0.0);   // the save's own frame
                    longest = std::max(longest, ms);
                    if (!adopted) PaceFrame(ms, o.fps);
                    if (adopted) {   // the swap's frame, and where its time went
                        const IsfHost::Split& sp = way.host->LastSplit();
                        way.swap.push_back(ms), way.adopt.push_back(adoptMs), way.handover.push_back(sp.handover);
                        way.draw.push_back(sp.draw), way.finish.push_back(lastFinishMs);
                    }
                }
                if (!errors.empty() || !adopted) {
                    std::fprintf(stderr, "sdfvj bench post: %s: the save did not build%s%s\n", name.c_str(), errors.empty() ? "" : ": ",
                                 errors.empty() ? "" : errors[0].c_str());
                    return 2;
                }
                way.toScreen.push_back(MsSince(t0));
                way.longest.push_back(longest);
                WarmGpu([&] { Frame(*way.host, input, w, h, in); }, 0.25);   // the clocks back up before the next
            }
        drift.endMs = steady(ways[0]);
        drifts.push_back(drift);
        for (Way& way : ways) {
            const double st = MedianMs(way.steady), ts = MedianMs(way.toScreen), lo = MedianMs(way.longest), sw = MedianMs(way.swap);
            std::printf("| %s | %s | %s | %.3f ms | %.1f ms | %.1f ms | %.1fx | %.2f ms | %.2f / %.2f / %.2f / %.2f ms |\n", name.c_str(),
                        SizeName(w, h).c_str(), way.name.c_str(), st, ts, lo, st > 0 ? lo / st : 0.0, sw, MedianMs(way.adopt), MedianMs(way.handover),
                        MedianMs(way.draw), MedianMs(way.finish));
            csv.Add(name, "post", SizeName(w, h), "fragment", st, gpu,
                    {way.name, std::to_string(ts), std::to_string(lo), std::to_string(sw), std::to_string(o.rounds)});
        }
        // In order: a rebuilt chain draws into the targets of the chain before the one it replaces
        // (IsfTexturePool), so from the second save on none are new.
        for (Way& way : ways) {
            std::string list;
            for (double ms : way.longest) list += (list.empty() ? "" : " / ") + std::to_string((int)std::lround(ms));
            std::printf("|  | | %s: the longest frame of each save in order | | | %s ms | | | |\n", way.name.c_str(), list.c_str());
            std::printf("|  | | %s: the first build's frame on screen, the longer of the next two | | | %.1f / %.1f ms | | | |\n",
                        way.name.c_str(), way.firstOn, way.firstNext);
        }
        std::fflush(stdout);
    }
    std::printf("\nmedians: steady of 10 interleaved blocks of %d frames; save -> screen and longest frame of %d saves each\n",
                std::max(5, o.frames / 10), o.rounds);
    for (const Drift& d : drifts) std::printf("%s\n", d.Line().c_str());
    glDeleteTextures(1, &input);
    if (!o.csv.empty() && !csv.Write(o.csv, &error)) std::fprintf(stderr, "sdfvj bench post: %s\n", error.c_str());
    std::error_code ec;
    fs::remove_all(work, ec);
    return 0;
}

}  // namespace sdfvj
