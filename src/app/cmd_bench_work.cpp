// `sdfvj bench work`: where a pixel's map() calls go. Each scene and lighting test is drawn twice
// with render.glsl's counting views (DEBUG_VIEW 6: the primary ray's march, normal, shadow ray and
// AO; 7: its reflection's), into a float target, and each phase's count is averaged over the
// frame's pixels. Counts, not milliseconds: they are the same on llvmpipe and on a GPU, so a lever
// that moves work between phases, or removes it, can be read here before it is timed. (A map()
// call is not a fixed cost: the fields skip shapes, the Mandelbulb leaves its orbit early.)
//
// "warp": what a GPU's 32-lane warp pays. The compute path's warps draw 8x4 pixel blocks (8-wide
// groups by rows, wider ones by WARP_BLOCKS), and a warp runs each phase's loop as long as its
// busiest lane: its cost is the sum over phases of the block's largest count, per pixel. The
// mean against it is the share of lanes busy.
#include <algorithm>
#include <cstdio>
#include <fstream>

#include "app/bench_support.h"
#include "app/commands.h"

namespace sdfvj {

namespace {

const char* const kPhases[8] = {"primary_march", "primary_normal", "primary_shadow", "primary_ao",
                                "reflection_march", "reflection_normal", "reflection_shadow", "reflection_ao"};

}  // namespace

int RunWorkBench(const WorkBenchOptions& o) {
    std::string error;
    auto fail = [&](int code) {
        std::fprintf(stderr, "sdfvj bench work: %s\n", error.c_str());
        return code;
    };
    int w = 0, h = 0;
    RenderPath path = RenderPath::Compute;
    if (!ParseSizeAndPath(o.size, o.path, &w, &h, &path, &error)) return fail(2);
    std::vector<LightingTest> known = SeedLightingTests();
    known.push_back(ShowLightingTest());
    known.push_back(ShowDirectReflectionsLightingTest());
    std::vector<LightingTest> tests;
    for (const std::string& name : o.tests) {
        bool found = false;
        for (const LightingTest& t : known)
            if (name == t.name) { tests.push_back(t); found = true; }
        if (!found) {
            error = "unknown lighting test '" + name + "', expected full, shadows_ao, shadows, none, show or show_direct";
            return fail(2);
        }
    }
    HeadlessContext gl;
    if (!gl.Create(&error)) return fail(2);
    FrameRenderer fr;
    if (!fr.Resize(w, h, &error, true)) return fail(2);

    std::string table = "| scene | lighting | pixels hit | march | normal | shadow | AO | refl. march | refl. normal | refl. shadow | refl. AO | total | warp | lanes busy |\n"
                        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    std::printf("# sdfvj bench work on %s, %dx%d, %s path: map() calls per pixel (mean over the frame), by phase; "
                "the cone pre-pass and probes of the floor's plane alone are not counted\n%s",
                gl.Description().c_str(), w, h, RenderPathName(path), table.c_str());
    BenchCsv csv;
    csv.extra = {"pixels_hit"};
    for (const char* p : kPhases) csv.extra.push_back(p);
    csv.extra.push_back("total");
    csv.extra.push_back("warp_total");
    const std::string gpu = GlRendererName();
    for (const std::string& name : o.scenes.empty() ? ListScenes() : o.scenes) {
        SceneInfo scene;
        if (!FindScene(name, &scene, &error)) return fail(2);
        FrameInputs in;
        for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
        in.time = 1.0;   // as `bench` draws
        for (const LightingTest& t : tests) {
            double mean[8] = {}, hit = 0.0;
            std::vector<float> counts(size_t(w) * size_t(h) * 8, 0.0f);   // every pixel's 8 phases
            for (int view : {4, 6, 7}) {   // 4: the geometry view, t >= 0 where the primary ray hit
                EffectSet e = t.effects;
                e.normals = scene.effects.normals;   // the scene's estimator, as `bench` draws
                e.debugView = view;
                ShaderSource src;
                Program program;
                if (!AssembleProgram(scene, VariantKey{scene.path, e, path}, &src, &error) || !program.Build(src, path, &error))
                    return fail(1);
                fr.Draw(program, scene, in);
                const std::vector<float> px = fr.ReadPixelsFloat();
                const size_t n = px.size() / 4;
                const double perPixel = 1.0 / double(std::max<size_t>(n, 1));
                for (size_t i = 0; i < n; ++i) {
                    if (view == 4) hit += px[4 * i] >= 0.0f ? perPixel : 0.0;
                    else
                        for (int c = 0; c < 4; ++c) {
                            mean[(view - 6) * 4 + c] += px[4 * i + c] * perPixel;
                            if (i < size_t(w) * size_t(h)) counts[8 * i + size_t(view - 6) * 4 + size_t(c)] = px[4 * i + c];
                        }
                }
            }
            double total = 0.0;
            for (double m : mean) total += m;
            // 8x4 blocks from pixel (0, 0), as the warps are laid out; partial blocks at the edges count
            // their pixels only.
            double warp = 0.0;
            for (int by = 0; by < h; by += 4)
                for (int bx = 0; bx < w; bx += 8) {
                    float most[8] = {};
                    for (int y = by; y < std::min(by + 4, h); ++y)
                        for (int x = bx; x < std::min(bx + 8, w); ++x)
                            for (int k = 0; k < 8; ++k) most[k] = std::max(most[k], counts[8 * (size_t(y) * size_t(w) + size_t(x)) + size_t(k)]);
                    const int lanes = (std::min(by + 4, h) - by) * (std::min(bx + 8, w) - bx);
                    for (float m : most) warp += double(m) * lanes;
                }
            warp /= double(std::max(w * h, 1));
            char row[600];
            std::snprintf(row, sizeof row, "| %s | %s | %.1f %% | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f %% |\n",
                          scene.name.c_str(), t.name, 100.0 * hit, mean[0], mean[1], mean[2], mean[3], mean[4], mean[5], mean[6],
                          mean[7], total, warp, warp > 0.0 ? 100.0 * total / warp : 100.0);
            std::printf("%s", row);
            std::fflush(stdout);
            table += row;
            std::vector<std::string> values;
            char v[64];
            std::snprintf(v, sizeof v, "%.4f", hit);
            values.push_back(v);
            for (double m : mean) {
                std::snprintf(v, sizeof v, "%.4f", m);
                values.push_back(v);
            }
            std::snprintf(v, sizeof v, "%.4f", total);
            values.push_back(v);
            std::snprintf(v, sizeof v, "%.4f", warp);
            values.push_back(v);
            csv.Add(scene.name, t.name, SizeName(w, h), RenderPathName(path), 0.0, gpu, values);
        }
    }
    if (!o.markdown.empty()) std::ofstream(o.markdown) << table;
    if (!o.csv.empty() && !csv.Write(o.csv, &error)) return fail(1);
    return 0;
}

}  // namespace sdfvj
