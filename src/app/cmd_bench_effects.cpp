// `sdfvj bench effects`: what the variant system saves. For each effect the scene can use:
//   (a) compiled out  — the program without it (what sdfvj runs when the effect is off)
//   (b) compiled in, switched off by the u_effectsOff uniform (what a single uber-shader runs)
//   (c) on
// Every program of the table (all effects, and the no-effects baseline) is drawn in each rotation,
// frame by frame, so clock drift hits all alike; the baseline is also timed alone at the start
// and the end (the drift check, bench_support.h).
// (b) - (a) is the cost of an effect that a uniform branch switches off; (a) against the
// baseline row shows that a compiled-out effect costs nothing.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>

#include "app/bench_support.h"
#include "app/commands.h"

namespace sdfvj {

namespace {

struct EffectCase {
    const char* name;
    int offBit;
    void (*enable)(EffectSet&);
    void (*disable)(EffectSet&);
};

}  // namespace

int RunEffectsBench(const EffectsBenchOptions& o) {
    std::string error;
    HeadlessContext gl;
    int w = 0, h = 0;
    if (!ParseSize(o.size, &w, &h, &error)) { std::fprintf(stderr, "sdfvj bench effects: %s\n", error.c_str()); return 2; }
    SceneInfo scene;
    if (!FindScene(o.scene, &scene, &error)) { std::fprintf(stderr, "sdfvj bench effects: %s\n", error.c_str()); return 2; }
    if (!gl.Create(&error)) { std::fprintf(stderr, "sdfvj bench effects: %s\n", error.c_str()); return 2; }
    RenderPath path = o.path == "compute" ? RenderPath::Compute : o.path == "fragment" ? RenderPath::Fragment
                                                                                      : ProbeRenderPath(scene, nullptr);
    const bool wallClock = IsSoftwareRenderer();
    FrameRenderer fr;
    if (!fr.Resize(w, h, &error)) { std::fprintf(stderr, "sdfvj bench effects: %s\n", error.c_str()); return 2; }
    FrameInputs in;
    in.time = 1.0;
    for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);

    auto build = [&](const EffectSet& e, std::unique_ptr<Program>* out) {
        ShaderSource src;
        *out = std::make_unique<Program>();
        return AssembleProgram(scene, VariantKey{scene.path, e, path}, &src, &error) && (*out)->Build(src, path, &error);
    };
    auto timeOnce = [&](const Program& p, int effectsOff) {
        in.effectsOff = effectsOff;
        fr.Draw(p, scene, in, true);
        return fr.LastGpuMs();
    };

    const EffectCase cases[] = {
        {"shadows", 1, [](EffectSet& e) { if (!e.shadows) e.shadows = 2; }, [](EffectSet& e) { e.shadows = 0; }},
        {"ao", 2, [](EffectSet& e) { e.ao = true; }, [](EffectSet& e) { e.ao = false; }},
        {"specular", 4, [](EffectSet& e) { e.specular = true; }, [](EffectSet& e) { e.specular = false; }},
        {"reflections=1", 8, [](EffectSet& e) { if (!e.reflections) e.reflections = 1; }, [](EffectSet& e) { e.reflections = 0; }},
        {"fog", 16, [](EffectSet& e) { e.fog = true; }, [](EffectSet& e) { e.fog = false; }},
    };
    char line[512];
    std::string table;
    std::snprintf(line, sizeof line,
                  "# sdfvj bench effects: %s at %dx%d, %s path, on %s\n# timing: %s, median of %d rotations after %d warm-up; "
                  "every program drawn in every rotation, 1 s warm-up after the compiles\n",
                  scene.name.c_str(), w, h, RenderPathName(path), gl.Description().c_str(),
                  wallClock ? "glFinish + wall clock" : "GL_TIME_ELAPSED", o.frames, o.warmup);
    std::printf("%s", line);
    table += "| effect (over the scene's own set) | (a) compiled out ms | (b) in, off by uniform ms | (c) on ms | (b)-(a) saved by variants ms | (c)-(a) cost of the effect ms |\n|---|---:|---:|---:|---:|---:|\n";
    std::printf("%s", table.c_str());

    // Every program first, so one rotation can draw them all: the baseline (no effects at all)
    // and per effect the program without it and the one with it.
    struct Timed { const Program* program; int effectsOff; std::vector<double> ms; };
    std::unique_ptr<Program> none;
    if (!build(EffectSet{}, &none)) { std::fprintf(stderr, "%s\n", error.c_str()); return 1; }
    std::vector<std::unique_ptr<Program>> keep;
    std::vector<Timed> timed = {{none.get(), 0, {}}};
    for (const EffectCase& c : cases) {
        EffectSet with = scene.effects, without = scene.effects;
        c.enable(with);
        c.disable(without);
        std::unique_ptr<Program> out, in_;
        if (!build(without, &out) || !build(with, &in_)) { std::fprintf(stderr, "%s\n", error.c_str()); return 1; }
        timed.push_back({out.get(), 0, {}});
        timed.push_back({in_.get(), c.offBit, {}});
        timed.push_back({in_.get(), 0, {}});
        keep.push_back(std::move(out));
        keep.push_back(std::move(in_));
    }
    WarmGpu([&] { for (Timed& t : timed) timeOnce(*t.program, t.effectsOff); });
    Drift drift;
    drift.label = scene.name + " no effects " + SizeName(w, h) + " " + RenderPathName(path);
    drift.startMs = TimeMedian([&] { return timeOnce(*none, 0); }, o.frames);
    for (int i = 0; i < o.warmup + o.frames; ++i)
        for (Timed& t : timed) {
            double ms = timeOnce(*t.program, t.effectsOff);
            if (i >= o.warmup) t.ms.push_back(ms);
        }
    drift.endMs = TimeMedian([&] { return timeOnce(*none, 0); }, o.frames);

    BenchCsv csv;
    csv.extra = {"effect", "variant"};
    const std::string size = SizeName(w, h), gpu = GlRendererName(), own = DescribeEffects(scene.effects);
    csv.Add(scene.name, "none", size, RenderPathName(path), MedianMs(timed[0].ms), gpu, {"(baseline)", "none"});
    for (size_t k = 0; k < std::size(cases); ++k) {
        const EffectCase& c = cases[k];
        double ma = MedianMs(timed[1 + 3 * k].ms), mb = MedianMs(timed[2 + 3 * k].ms), mc = MedianMs(timed[3 + 3 * k].ms);
        std::snprintf(line, sizeof line, "| %s | %.3f | %.3f | %.3f | %.3f | %.3f |\n", c.name, ma, mb, mc, mb - ma, mc - ma);
        std::printf("%s", line);
        table += line;
        csv.Add(scene.name, own, size, RenderPathName(path), ma, gpu, {c.name, "compiled_out"});
        csv.Add(scene.name, own, size, RenderPathName(path), mb, gpu, {c.name, "off_by_uniform"});
        csv.Add(scene.name, own, size, RenderPathName(path), mc, gpu, {c.name, "on"});
    }
    std::snprintf(line, sizeof line, "| (baseline: no effects, interleaved) | %.3f | | | | |\n\n%s\n", MedianMs(timed[0].ms),
                  drift.Line().c_str());
    std::printf("%s", line);
    table += line;
    if (!o.csv.empty() && !csv.Write(o.csv, &error)) { std::fprintf(stderr, "sdfvj bench effects: %s\n", error.c_str()); return 1; }
    if (!o.markdown.empty()) {
        std::ofstream md(o.markdown);
        md << "Scene " << scene.name << " at " << w << "x" << h << ", " << RenderPathName(path) << " path, "
           << gl.Description() << "; scene's own effects: " << DescribeEffects(scene.effects) << "\n\n" << table;
    }
    return 0;
}

}  // namespace sdfvj
