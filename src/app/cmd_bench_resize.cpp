// `sdfvj bench resize`: what a change of the render scale costs the show's frame (`live`'s
// resolution slider, and --frame-budget, which moves the scale about once a second). Each frame
// is drawn as `live` draws it in-process: the scene at scale x the window into FrameRenderer's
// target, the post chain (if any) over it at that size, the result scaled to the window's size.
// Two ways, interleaved round by round, each with its own renderer and chain:
//   kept sizes   targets of the last --keep other sizes kept (FrameRenderer::SetKeptSizes,
//                IsfHost::SetKeptSizes), so a return to a size allocates nothing
//   new targets  every change allocates (as before session 33)
// Per way and scale: the frame that changed to it (the first visit, then the median of later
// ones) and the frame after it (a post target is two textures drawn in turn), against the
// steady frame at that scale.
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "app/bench_support.h"
#include "app/commands.h"
#include "app/show.h"
#include "isf/isf_host.h"
#include "render/render.h"

namespace sdfvj {

namespace {

struct Way {
    std::string name;
    int keep = 0;
    FrameRenderer renderer;
    std::unique_ptr<IsfHost> host;
    float scale = 1.0f;
    std::map<float, std::vector<double>> first, later, after, steady;   // by scale
};

}  // namespace

int RunResizeBench(const ResizeBenchOptions& o) {
    std::string error;
    auto fail = [&](int code) {
        std::fprintf(stderr, "sdfvj bench resize: %s\n", error.c_str());
        return code;
    };
    int w = 0, h = 0;
    RenderPath path = RenderPath::Compute;
    if (!ParseSizeAndPath(o.size, o.path, &w, &h, &path, &error)) return fail(2);
    std::vector<float> scales;
    {
        std::stringstream list(o.scales);
        for (std::string item; std::getline(list, item, ',');) {
            char* end = nullptr;
            const float s = std::strtof(item.c_str(), &end);
            if (item.empty() || *end || !(s >= 0.25f && s <= 2.0f)) {
                error = "--scales: \"" + item + "\" is not a scale, expected numbers in 0.25..2 separated by commas";
                return fail(2);
            }
            scales.push_back(s);
        }
    }
    if (scales.size() < 2) {
        error = "--scales: at least two scales, the first the one the show starts at";
        return fail(2);
    }
    HeadlessContext gl;
    if (!gl.Create(&error)) return fail(2);
    SceneInfo scene;
    if (!FindScene(o.scene, &scene, &error)) return fail(2);
    ShaderSource src;
    Program program;
    if (!AssembleProgram(scene, VariantKey{scene.path, scene.effects, path}, &src, &error) || !program.Build(src, path, &error))
        return fail(1);
    FrameInputs in;
    for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
    std::vector<IsfFile> post;
    if (!o.post.empty())
        for (const std::string& f : SplitIsfList(o.post)) {
            IsfFile file;
            if (!LoadIsfFile(ResolveIsfPath(f), &file, &error)) return fail(2);
            post.push_back(std::move(file));
        }
    // The window: what the frame is scaled to at the end.
    unsigned windowTex = 0, windowFbo = 0, readFbo = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &windowTex);
    glTextureStorage2D(windowTex, 1, GL_RGBA8, w, h);
    glCreateFramebuffers(1, &windowFbo);
    glNamedFramebufferTexture(windowFbo, GL_COLOR_ATTACHMENT0, windowTex, 0);
    glCreateFramebuffers(1, &readFbo);
    Way ways[2];
    ways[0].name = "kept sizes (" + std::to_string(o.keep) + ")";
    ways[0].keep = o.keep;
    ways[1].name = "new targets";
    IsfFrameInputs pin;
    auto frame = [&](Way& way, float scale) {
        const auto t0 = Clock::now();
        const int rw = std::max(1, (int)std::lround(w * scale)), rh = std::max(1, (int)std::lround(h * scale));
        std::string e;
        if (!way.renderer.Resize(rw, rh, &e)) return -1.0;
        ++in.frame;
        in.time += 1.0 / 60.0;
        way.renderer.Draw(program, scene, in);
        unsigned out = way.renderer.Texture();
        if (way.host) {
            IsfHost::Done done;
            way.host->Poll(&done);
            pin.time = in.time;
            ++pin.frame;
            out = way.host->Render(out, rw, rh, pin);
        }
        glNamedFramebufferTexture(readFbo, GL_COLOR_ATTACHMENT0, out, 0);
        glBlitNamedFramebuffer(readFbo, windowFbo, 0, 0, rw, rh, 0, 0, w, h, GL_COLOR_BUFFER_BIT, rw == w && rh == h ? GL_NEAREST : GL_LINEAR);
        glFinish();
        way.scale = scale;
        return MsSince(t0);
    };
    for (Way& way : ways) {
        way.renderer.SetKeptSizes(way.keep);
        if (!post.empty()) {
            way.host = std::make_unique<IsfHost>();   // built here; drawn here, as `live` draws it on NVIDIA
            way.host->SetKeptSizes(way.keep);
            way.host->Request(post, w, h);
            IsfHost::Done done;
            if (!way.host->Poll(&done) || !done.adopted) {
                error = "the post chain did not build" + (done.errors.empty() ? std::string() : ": " + done.errors[0]);
                return fail(1);
            }
        }
        if (frame(way, scales[0]) < 0) {
            error = "cannot draw at " + SizeName(w, h);
            return fail(1);
        }
    }
    const std::string gpu = (const char*)glGetString(GL_RENDERER);
    std::printf("# sdfvj bench resize: %s at %s (%s path)%s on %s\nscales %s, %d rounds, frames paced at %.0f fps\n\n", scene.name.c_str(),
                SizeName(w, h).c_str(), RenderPathName(path), post.empty() ? "" : (", post " + o.post).c_str(), gpu.c_str(),
                o.scales.c_str(), o.rounds, o.fps);
    WarmGpu([&] { for (Way& way : ways) frame(way, scales[0]); }, 1.0);
    Drift drift{scene.name + " " + SizeName(w, h) + " steady at scale " + std::to_string(scales[0]).substr(0, 4)};
    drift.startMs = TimeMedian([&] { return frame(ways[0], scales[0]); }, 10);
    // Rounds: each way visits every scale in turn and comes back to the first; which way goes first alternates.
    for (int round = 0; round < o.rounds; ++round)
        for (int j = 0; j < 2; ++j) {
            Way& way = ways[(round + j) % 2];
            for (size_t k = 1; k <= scales.size(); ++k) {
                const float s = scales[k % scales.size()];
                const double change = frame(way, s), next = frame(way, s);
                (way.first.count(s) ? way.later[s] : way.first[s]).push_back(change);
                way.after[s].push_back(next);
                PaceFrame(next, o.fps);
                for (int f = 0; f < 6; ++f) {
                    const double ms = frame(way, s);
                    if (f >= 2) way.steady[s].push_back(ms);
                    PaceFrame(ms, o.fps);
                }
            }
        }
    drift.endMs = TimeMedian([&] { return frame(ways[0], scales[0]); }, 10);
    std::printf("| scale | size | way | steady frame | the change's frame, first visit | later visits (median) | the frame after (median) |\n"
                "|---:|---|---|---:|---:|---:|---:|\n");
    BenchCsv csv;
    csv.extra = {"way", "scale", "first_change_ms", "later_change_ms", "after_ms"};
    for (const float s : scales)
        for (Way& way : ways) {
            const int rw = std::max(1, (int)std::lround(w * s)), rh = std::max(1, (int)std::lround(h * s));
            const double st = MedianMs(way.steady[s]), first = way.first[s].empty() ? 0.0 : way.first[s][0];
            const double later = MedianMs(way.later[s]), after = MedianMs(way.after[s]);
            std::printf("| %.2f | %s | %s | %.3f ms | %.2f ms | %.2f ms | %.3f ms |\n", s, SizeName(rw, rh).c_str(), way.name.c_str(), st,
                        first, later, after);
            csv.Add(scene.name, post.empty() ? "scene" : "scene+post", SizeName(w, h), RenderPathName(path), st, gpu,
                    {way.name, std::to_string(s), std::to_string(first), std::to_string(later), std::to_string(after)});
        }
    std::printf("\nsteady: median of frames 3..6 after each change; later visits: rounds 2..%d\n%s\n", o.rounds, drift.Line().c_str());
    for (Way& way : ways) std::printf("%s: %d scene targets made\n", way.name.c_str(), way.renderer.TargetsMade());
    glDeleteFramebuffers(1, &readFbo);
    glDeleteFramebuffers(1, &windowFbo);
    glDeleteTextures(1, &windowTex);
    for (Way& way : ways) way.host.reset();
    if (!o.csv.empty() && !csv.Write(o.csv, &error)) return fail(1);
    return 0;
}

}  // namespace sdfvj
