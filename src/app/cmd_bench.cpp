// `sdfvj bench`: GPU milliseconds per frame, every scene x the seed's four lighting tests x sizes
// x both render paths. Median of N frames after warm-up; GL timer queries on a real GPU, glFinish
// and a wall clock on llvmpipe (whose timer queries are meaningless).
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>

#include "app/commands.h"

namespace sdfvj {


int RunBench(const BenchOptions& o) {
    std::string error;
    HeadlessContext gl;
    if (!gl.Create(&error)) { std::fprintf(stderr, "sdfvj bench: %s\n", error.c_str()); return 2; }
    const bool wallClock = IsSoftwareRenderer();
    std::printf("# sdfvj bench on %s\n# timing: %s, median of %d frames after %d warm-up\n", gl.Description().c_str(),
                wallClock ? "glFinish + wall clock (software renderer)" : "GL_TIME_ELAPSED", o.frames, o.warmup);

    std::vector<std::string> scenes = o.scenes.empty() ? ListScenes() : o.scenes;
    std::vector<LightingTest> tests;
    for (const auto& t : SeedLightingTests())
        if (o.tests.empty() || std::find(o.tests.begin(), o.tests.end(), t.name) != o.tests.end()) tests.push_back(t);
    if (tests.empty()) { std::fprintf(stderr, "sdfvj bench: no lighting test matches, expected full, shadows_ao, shadows or none\n"); return 2; }
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

    FrameRenderer fr;
    for (const std::string& name : scenes) {
        SceneInfo scene;
        if (!FindScene(name, &scene, &error)) { std::fprintf(stderr, "sdfvj bench: %s\n", error.c_str()); return 2; }
        FrameInputs in;
        for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
        in.time = 1.0;
        for (const LightingTest& t : tests) {
            std::map<RenderPath, std::unique_ptr<Program>> programs;
            for (RenderPath p : paths) {
                ShaderSource src;
                EffectSet e = t.effects;
                VariantKey key{scene.path, e, p};
                auto prog = std::make_unique<Program>();
                if (!AssembleProgram(scene, key, &src, &error) || !prog->Build(src, p, &error)) {
                    std::fprintf(stderr, "sdfvj bench: %s\n", error.c_str());
                    return 1;
                }
                programs[p] = std::move(prog);
            }
            for (auto [w, h] : sizes) {
                if (!fr.Resize(w, h, &error)) { std::fprintf(stderr, "sdfvj bench: %s\n", error.c_str()); return 2; }
                char row[256];
                std::snprintf(row, sizeof row, "| %s | %s | %dx%d |", scene.name.c_str(), t.name, w, h);
                std::string line = row;
                std::vector<double> medians;
                for (RenderPath p : paths) {
                    std::vector<double> ms;
                    for (int i = 0; i < o.warmup + o.frames; ++i) {
                        in.frame = i;
                        fr.Draw(*programs[p], scene, in, true);
                        if (i >= o.warmup) ms.push_back(fr.LastGpuMs());
                    }
                    medians.push_back(MedianMs(ms));
                    std::snprintf(row, sizeof row, " %.3f |", medians.back());
                    line += row;
                }
                if (medians.size() == 2) {
                    std::snprintf(row, sizeof row, " %.2f |", medians[1] > 0 ? medians[0] / medians[1] : 0.0);
                    line += row;
                }
                std::printf("%s\n", line.c_str());
                std::fflush(stdout);
                table += line + "\n";
            }
        }
    }
    if (!o.markdown.empty()) {
        std::ofstream md(o.markdown);
        md << "Measured on " << gl.Description() << " (" << (wallClock ? "wall clock" : "GL_TIME_ELAPSED")
           << ", median of " << o.frames << " frames after " << o.warmup << " warm-up)\n\n" << table;
    }
    return 0;
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
