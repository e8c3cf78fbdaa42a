// `sdfvj bench`: GPU milliseconds per frame, every scene x the seed's four lighting tests x sizes
// x both render paths. Median of N frames after warm-up; GL timer queries on a real GPU, glFinish
// and a wall clock on llvmpipe (whose timer queries are meaningless). Trusted as bench_support.h
// says: 1 s warm-up after the compiles, every cell interleaved, a drift check, --csv.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>

#include "app/bench_support.h"
#include "app/commands.h"
#include "render/live_program.h"

namespace sdfvj {


int RunBench(const BenchOptions& o) {
    std::string error;
    HeadlessContext gl;
    if (!gl.Create(&error)) { std::fprintf(stderr, "sdfvj bench: %s\n", error.c_str()); return 2; }
    const bool wallClock = IsSoftwareRenderer();
    const std::string gpu = GlRendererName();
    std::printf("# sdfvj bench on %s\n# timing: %s, median of %d frames after %d warm-up; every program warmed %.1f s "
                "after the compiles; every scene, test, size and path interleaved frame by frame\n",
                gl.Description().c_str(), wallClock ? "glFinish + wall clock (software renderer)" : "GL_TIME_ELAPSED",
                o.frames, o.warmup, 1.0);

    std::vector<std::string> scenes = o.scenes.empty() ? ListScenes() : o.scenes;
    std::vector<LightingTest> tests;
    std::vector<LightingTest> known = SeedLightingTests();
    known.push_back(ShowLightingTest());
    known.push_back(ShowSupersampledLightingTest(false));
    known.push_back(ShowSupersampledLightingTest(true));
    known.push_back(ShowDirectReflectionsLightingTest());
    known.push_back(ShowQuadReflectionsLightingTest());
    known.push_back(FullQuadShadeLightingTest());
    for (const LightingTest& t : FramePartTests()) known.push_back(t);
    for (const std::string& name : o.tests)
        if (std::none_of(known.begin(), known.end(), [&](const LightingTest& t) { return name == t.name; })) {
            std::fprintf(stderr, "sdfvj bench: unknown lighting test '%s', expected full, shadows_ao, shadows, none, show, show_ssaa, show_ssaa_exact, show_direct, show_quad_reflections, full_quad_shade, march or normals\n", name.c_str());
            return 2;
        }
    for (const auto& t : o.tests.empty() ? SeedLightingTests() : known)   // a bare bench: the seed's four
        if (o.tests.empty() || std::find(o.tests.begin(), o.tests.end(), t.name) != o.tests.end()) tests.push_back(t);
    std::vector<std::pair<int, int>> sizes;
    for (const auto& s : o.sizes) {
        int w, h;
        if (!ParseSize(s, &w, &h, &error)) { std::fprintf(stderr, "sdfvj bench: %s\n", error.c_str()); return 2; }
        sizes.emplace_back(w, h);
    }
    std::vector<RenderPath> paths;
    for (const auto& p : o.paths) {
        if (p == "fragment") paths.push_back(RenderPath::Fragment);
        else if (p == "compute") paths.push_back(RenderPath::Compute);
        else { std::fprintf(stderr, "sdfvj bench: unknown path '%s', expected fragment or compute\n", p.c_str()); return 2; }
    }

    std::string table = "| scene | lighting | size |";
    for (RenderPath p : paths) table += std::string(" ") + RenderPathName(p) + " ms |";
    if (paths.size() == 2) table += " fragment/compute |";
    table += "\n|---|---|---|";
    for (size_t i = 0; i < paths.size() + (paths.size() == 2 ? 1 : 0); ++i) table += "---:|";
    table += "\n";
    std::printf("%s", table.c_str());
    std::fflush(stdout);

    BenchCsv csv;
    // One target per size, so all sizes interleave without reallocating.
    std::vector<std::unique_ptr<FrameRenderer>> targets;
    // SDFVJ_QUAD_DEFER_ROOM=N (a measurement's knob): the room of a `quad_reflections` list
    // (quad_reflections.glsl QUAD_REFLECTIONS_DEFER; FrameRenderer::SetQuadDeferRoom); 0 times a listing
    // program with every bounce traced in the frame.
    const long long deferRoom = EnvInt("SDFVJ_QUAD_DEFER_ROOM", -1, 0, INT_MAX);
    if (const char* env = std::getenv("SDFVJ_QUAD_DEFER_ROOM"); env && *env && deferRoom < 0) {
        std::fprintf(stderr, "sdfvj bench: SDFVJ_QUAD_DEFER_ROOM=%s: expected a count of entries, 0 or more\n", env);
        return 2;
    }
    for (auto [w, h] : sizes) {
        targets.push_back(std::make_unique<FrameRenderer>());
        if (!targets.back()->Resize(w, h, &error)) { std::fprintf(stderr, "sdfvj bench: %s\n", error.c_str()); return 2; }
        targets.back()->SetQuadDeferRoom(deferRoom);
    }
    // Every program first: each (scene, test, size, path) is one setting, and each round draws
    // every setting once, so a clock change lands on all of them alike (scenes and sizes are
    // compared across rows: the scaling tables of docs/performance.md).
    struct Cell { size_t scene, test, size; RenderPath path; Program* program; std::vector<double> ms; };
    std::vector<SceneInfo> infos;
    std::vector<FrameInputs> inputs;
    std::vector<std::unique_ptr<Program>> programs;
    std::vector<Cell> cells;
    for (const std::string& name : scenes) {
        SceneInfo scene;
        // NAME:literals times the literal tier's program (live's first tier of a save that only retunes
        // numbers: the scene's float literals read from uniforms) beside NAME's own.
        // NAME:aoN draws NAME with N AO samples (the quality knob, a uniform) beside NAME's default.
        std::string sceneName = name;
        int aoSamples = -1;
        if (const size_t at = name.rfind(":ao"); at != std::string::npos && at + 3 < name.size() &&
                                                  name.find_first_not_of("0123456789", at + 3) == std::string::npos) {
            aoSamples = std::atoi(name.c_str() + at + 3);
            if (name.size() - at > 5 || aoSamples < 1 || aoSamples > 64) {
                std::fprintf(stderr, "sdfvj bench: %s: AO samples between 1 and 64 expected after ':ao'\n", name.c_str());
                return 2;
            }
            sceneName = name.substr(0, at);
        }
        const std::string kLiterals = ":literals";
        const bool lift = sceneName.size() > kLiterals.size() &&
                          sceneName.compare(sceneName.size() - kLiterals.size(), kLiterals.size(), kLiterals) == 0;
        if (lift) sceneName.resize(sceneName.size() - kLiterals.size());
        if (!FindScene(sceneName, &scene, &error)) { std::fprintf(stderr, "sdfvj bench: %s\n", error.c_str()); return 2; }
        if (lift) scene.name += kLiterals;
        if (aoSamples > 0) scene.name += ":ao" + std::to_string(aoSamples);
        FrameInputs in;
        for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
        in.time = 1.0;
        if (aoSamples > 0) in.quality.aoSamples = aoSamples;
        for (size_t t = 0; t < tests.size(); ++t)
            for (RenderPath p : paths) {
                ShaderSource src;
                auto prog = std::make_unique<Program>();
                EffectSet effects = tests[t].effects;
                effects.normals = scene.effects.normals;   // the normal estimator is the scene's, not a lighting choice
                if (!AssembleProgram(scene, VariantKey{scene.path, effects, p}, &src, &error, lift) ||
                    !prog->Build(src, p, &error)) {
                    std::fprintf(stderr, "sdfvj bench: %s\n", error.c_str());
                    return 1;
                }
                for (size_t s = 0; s < sizes.size(); ++s) cells.push_back({infos.size(), t, s, p, prog.get(), {}});
                programs.push_back(std::move(prog));
            }
        infos.push_back(scene);
        inputs.push_back(in);
    }
    auto draw = [&](Cell& c, int frame) {
        inputs[c.scene].frame = frame;
        targets[c.size]->Draw(*c.program, infos[c.scene], inputs[c.scene], true);
        return targets[c.size]->LastGpuMs();
    };
    std::fprintf(stderr, "sdfvj bench: %zu programs compiled, %zu settings; warming up\n", programs.size(), cells.size());
    WarmGpu([&] { for (Cell& c : cells) draw(c, 0); });
    Drift drift;
    if (!cells.empty()) {
        const Cell& c = cells[0];
        drift.label = infos[c.scene].name + " " + tests[c.test].name + " " + SizeName(sizes[c.size].first, sizes[c.size].second) +
                      " " + RenderPathName(c.path);
        drift.startMs = TimeMedian([&] { return draw(cells[0], 0); }, o.frames);
    }
    for (int i = 0; i < o.warmup + o.frames; ++i)
        for (Cell& c : cells) {
            double ms = draw(c, i);
            if (i >= o.warmup) c.ms.push_back(ms);
        }
    if (!cells.empty()) drift.endMs = TimeMedian([&] { return draw(cells[0], 0); }, o.frames);

    for (size_t sc = 0; sc < infos.size(); ++sc)
        for (size_t t = 0; t < tests.size(); ++t)
            for (size_t s = 0; s < sizes.size(); ++s) {
                auto [w, h] = sizes[s];
                char row[256];
                std::snprintf(row, sizeof row, "| %s | %s | %dx%d |", infos[sc].name.c_str(), tests[t].name, w, h);
                std::string line = row;
                std::vector<double> medians;
                for (RenderPath p : paths)
                    for (Cell& c : cells) {
                        if (c.scene != sc || c.test != t || c.size != s || c.path != p) continue;
                        medians.push_back(MedianMs(c.ms));
                        csv.Add(infos[sc].name, tests[t].name, SizeName(w, h), RenderPathName(p), medians.back(), gpu);
                        std::snprintf(row, sizeof row, " %.3f |", medians.back());
                        line += row;
                    }
                if (medians.size() == 2) {
                    std::snprintf(row, sizeof row, " %.2f |", medians[1] > 0 ? medians[0] / medians[1] : 0.0);
                    line += row;
                }
                std::printf("%s\n", line.c_str());
                table += line + "\n";
            }
    if (!cells.empty()) {
        std::printf("%s\n", drift.Line().c_str());
        table += "\n" + drift.Line() + "\n";
    }
    if (!o.markdown.empty()) {
        std::ofstream md(o.markdown);
        md << "Measured on " << gl.Description() << " (" << (wallClock ? "wall clock" : "GL_TIME_ELAPSED")
           << ", median of " << o.frames << " frames after " << o.warmup << " warm-up, 1 s warm-up after each compile)\n\n"
           << table;
    }
    if (!o.csv.empty() && !csv.Write(o.csv, &error)) { std::fprintf(stderr, "sdfvj bench: %s\n", error.c_str()); return 1; }
    return 0;   // a drift is reported in the table, not an error
}

int RunList() {
    std::printf("Scenes (shaders/scenes):\n");
    for (const auto& name : ListScenes()) {
        SceneInfo s;
        std::string err;
        if (!FindScene(name, &s, &err)) { std::printf("  %-12s  BROKEN: %s\n", name.c_str(), err.c_str()); continue; }
        std::string params;
        for (const auto& p : s.params) params += (params.empty() ? "" : " ") + p.name;
        std::printf("  %-12s  %s\n  %-12s  effects: %s; params: %s\n", name.c_str(), s.description.c_str(), "",
                    DescribeEffects(s.effects).c_str(), params.empty() ? "(none)" : params.c_str());
    }
    std::printf("Presets (presets):\n");
    for (const auto& name : ListPresets()) std::printf("  %s\n", name.c_str());
    return 0;
}

}  // namespace sdfvj
