// `sdfvj bench effects`: what the variant system saves. For each effect the scene can use:
//   (a) compiled out  — the program without it (what sdfvj runs when the effect is off)
//   (b) compiled in, switched off by the u_effectsOff uniform (what a single uber-shader runs)
//   (c) on
// The three programs are drawn in rotation, frame by frame, so clock drift hits all alike.
// (b) - (a) is the cost of an effect that a uniform branch switches off; (a) against the
// baseline row shows that a compiled-out effect costs nothing.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

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
                  "# sdfvj bench effects: %s at %dx%d, %s path, on %s\n# timing: %s, median of %d rotations after %d warm-up\n",
                  scene.name.c_str(), w, h, RenderPathName(path), gl.Description().c_str(),
                  wallClock ? "glFinish + wall clock" : "GL_TIME_ELAPSED", o.frames, o.warmup);
    std::printf("%s", line);
    table += "| effect (over the scene's own set) | (a) compiled out ms | (b) in, off by uniform ms | (c) on ms | (b)-(a) saved by variants ms | (c)-(a) cost of the effect ms |\n|---|---:|---:|---:|---:|---:|\n";
    std::printf("%s", table.c_str());

    // Baseline: no effects at all, measured at the start and the end (its spread is the noise).
    std::unique_ptr<Program> none;
    if (!build(EffectSet{}, &none)) { std::fprintf(stderr, "%s\n", error.c_str()); return 1; }
    std::vector<double> noneA, noneB;
    for (int i = 0; i < o.warmup + o.frames; ++i) { double t = timeOnce(*none, 0); if (i >= o.warmup) noneA.push_back(t); }

    for (const EffectCase& c : cases) {
        EffectSet with = scene.effects, without = scene.effects;
        c.enable(with);
        c.disable(without);
        std::unique_ptr<Program> out, in_;
        if (!build(without, &out) || !build(with, &in_)) { std::fprintf(stderr, "%s\n", error.c_str()); return 1; }
        std::vector<double> a, b, on;
        for (int i = 0; i < o.warmup + o.frames; ++i) {
            double ta = timeOnce(*out, 0), tb = timeOnce(*in_, c.offBit), tc = timeOnce(*in_, 0);
            if (i < o.warmup) continue;
            a.push_back(ta);
            b.push_back(tb);
            on.push_back(tc);
        }
        double ma = MedianMs(a), mb = MedianMs(b), mc = MedianMs(on);
        std::snprintf(line, sizeof line, "| %s | %.3f | %.3f | %.3f | %.3f | %.3f |\n", c.name, ma, mb, mc, mb - ma, mc - ma);
        std::printf("%s", line);
        table += line;
    }
    for (int i = 0; i < o.frames; ++i) noneB.push_back(timeOnce(*none, 0));
    std::snprintf(line, sizeof line, "| (baseline: no effects, start / end of run) | %.3f / %.3f | | | | |\n", MedianMs(noneA), MedianMs(noneB));
    std::printf("%s", line);
    table += line;
    if (!o.markdown.empty()) {
        std::ofstream md(o.markdown);
        md << "Scene " << scene.name << " at " << w << "x" << h << ", " << RenderPathName(path) << " path, "
           << gl.Description() << "; scene's own effects: " << DescribeEffects(scene.effects) << "\n\n" << table;
    }
    return 0;
}

}  // namespace sdfvj
