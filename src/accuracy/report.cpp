// Reports of the sweep: CSV, time-against-error plots (PNG, SVG) and docs/accuracy.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "accuracy/accuracy.h"

namespace sdfvj::accuracy {

namespace {

const auto F = Format;

// Plot frame: x = GPU ms (log10 over the scene's range), y = % pixels > 8/255 off (log10,
// 1e-3 .. 100; 0 % is drawn at 1e-3).
struct Frame {
    int w = 720, h = 450, left = 70, right = 20, top = 30, bottom = 50;
    double xmin = 0.1, xmax = 1;
    double X(double ms) const {
        double a = std::log10(xmin), b = std::log10(xmax), v = std::log10(std::clamp(ms, xmin, xmax));
        return left + (w - left - right) * (v - a) / std::max(b - a, 1e-9);
    }
    double Y(double pct) const {
        double l = std::log10(std::clamp(pct, 1e-3, 100.0));
        return top + (h - top - bottom) * (2.0 - l) / 5.0;
    }
};

Frame MakeFrame(const std::vector<Row>& rows, const std::string& scene) {
    Frame f;
    double lo = 1e30, hi = 0;
    for (const Row& r : rows)
        if (r.scene == scene && r.gpuMs > 0) { lo = std::min(lo, r.gpuMs); hi = std::max(hi, r.gpuMs); }
    if (hi <= 0) { lo = 0.1; hi = 1; }
    f.xmin = lo / 1.15;
    f.xmax = hi * 1.15;
    return f;
}

// 1, 2, 5 x 10^k inside the frame's x range.
std::vector<double> XTicks(const Frame& f) {
    std::vector<double> v;
    for (int k = -3; k <= 5; ++k)
        for (double m : {1.0, 2.0, 5.0}) {
            double x = m * std::pow(10.0, k);
            if (x >= f.xmin && x <= f.xmax) v.push_back(x);
        }
    return v;
}

// The scene's Pareto front: of the quality rows, or (scales) of the render-scale rows, whose error
// is against the supersampled truth and which form a front of their own (MarkPareto).
bool ScaleRow(const Row& r) { return r.s.knob == "scale"; }
std::vector<const Row*> Front(const std::vector<Row>& rows, const std::string& scene, bool scales) {
    std::vector<const Row*> v;
    for (const Row& r : rows)
        if (r.scene == scene && r.pareto && ScaleRow(r) == scales) v.push_back(&r);
    std::sort(v.begin(), v.end(), [](const Row* a, const Row* b) { return a->gpuMs < b->gpuMs; });
    return v;
}

// Penumbra and AO samples change the look (each is compared with its own reference), and render
// scales are compared with the supersampled truth: never offered as the "cheapest setting" for an
// error budget.
bool LookKnob(const Row& r) { return r.s.knob == "penumbra" || r.s.knob == "ao_samples" || ScaleRow(r); }

std::string Esc(const std::string& s) {
    std::string o;
    for (char c : s) o += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
    return o;
}

}  // namespace

std::string CsvHeader() {
    return "scene,knob,setting,role,max_steps,hit_eps,eps_mode,step_factor,naive_step,normals,normal_eps,march_fixed,"
           "fixed_step,shadow_steps,shadow_k,ao_samples,gpu_ms,pct_over_8,psnr_db,t_err_p50_px,t_err_p99_px,"
           "t_err_max_px,silhouette_pct,normal_p50_deg,normal_p99_deg,out_of_steps_pct,ref_out_of_steps_pct,pareto,render_scale,pct_over_8_scene_look";
}

std::string CsvLine(const Row& r) {
    const Setting& s = r.s;
    std::ostringstream o;
    o << r.scene << "," << s.knob << ",\"" << s.label << "\"," << s.role << "," << s.q.maxSteps << "," << s.q.hitEps << ","
      << s.epsMode << "," << s.q.stepFactor << "," << (s.naiveStep ? 1 : 0) << "," << s.normals << "," << s.q.normalEps
      << "," << (s.marchFixed ? 1 : 0) << "," << s.q.fixedStep << "," << s.q.shadowSteps << "," << s.q.shadowK << ","
      << s.q.aoSamples << "," << F("%.4f", r.gpuMs) << "," << F("%.4f", r.img.pctOver8) << "," << F("%.2f", r.img.psnr)
      << "," << F("%.4g", r.g.tErrP50) << "," << F("%.4g", r.g.tErrP99) << "," << F("%.4g", r.g.tErrMax) << ","
      << F("%.4f", r.g.silhouettePct) << "," << F("%.4g", r.g.normalP50) << "," << F("%.4g", r.g.normalP99) << ","
      << F("%.4f", r.g.outOfStepsPct) << "," << F("%.4f", r.g.refOutOfStepsPct) << "," << (r.pareto ? 1 : 0) << "," << F("%g", s.scale) << "," << F("%.4f", r.imgSceneLook.pctOver8);
    return o.str();
}

bool WritePlotPng(const std::string& path, const std::vector<Row>& rows, const std::string& scene, std::string* error) {
    Frame f = MakeFrame(rows, scene);
    std::vector<uint8_t> img((size_t)f.w * f.h * 4, 255);
    auto put = [&](int x, int y, uint8_t r, uint8_t g, uint8_t b) {
        if (x < 0 || y < 0 || x >= f.w || y >= f.h) return;
        uint8_t* p = &img[((size_t)y * f.w + x) * 4];
        p[0] = r; p[1] = g; p[2] = b; p[3] = 255;
    };
    auto line = [&](double x0, double y0, double x1, double y1, uint8_t r, uint8_t g, uint8_t b) {
        int n = (int)std::max(std::fabs(x1 - x0), std::fabs(y1 - y0)) + 1;
        for (int i = 0; i <= n; ++i) put((int)std::lround(x0 + (x1 - x0) * i / n), (int)std::lround(y0 + (y1 - y0) * i / n), r, g, b);
    };
    auto dot = [&](double x, double y, int rad, uint8_t r, uint8_t g, uint8_t b) {
        for (int dy = -rad; dy <= rad; ++dy)
            for (int dx = -rad; dx <= rad; ++dx)
                if (dx * dx + dy * dy <= rad * rad) put((int)std::lround(x) + dx, (int)std::lround(y) + dy, r, g, b);
    };
    // axes and decade grid lines
    for (int d = -3; d <= 2; ++d) line(f.left, f.Y(std::pow(10.0, d)), f.w - f.right, f.Y(std::pow(10.0, d)), 225, 225, 225);
    for (double v : XTicks(f)) line(f.X(v), f.top, f.X(v), f.h - f.bottom, 235, 235, 235);
    line(f.left, f.top, f.left, f.h - f.bottom, 0, 0, 0);
    line(f.left, f.h - f.bottom, f.w - f.right, f.h - f.bottom, 0, 0, 0);
    line(f.left, f.Y(0.1), f.w - f.right, f.Y(0.1), 240, 160, 160);   // the 0.1 % target
    for (bool scales : {false, true}) {
        auto front = Front(rows, scene, scales);
        for (size_t i = 1; i < front.size(); ++i)
            line(f.X(front[i - 1]->gpuMs), f.Y(front[i - 1]->img.pctOver8), f.X(front[i]->gpuMs), f.Y(front[i]->img.pctOver8),
                 scales ? 230 : 200, scales ? 140 : 30, scales ? 0 : 30);
    }
    for (const Row& r : rows) {
        if (r.scene != scene) continue;
        double x = f.X(r.gpuMs), y = f.Y(r.img.pctOver8);
        if (ScaleRow(r)) dot(x, y, r.pareto ? 4 : 3, 230, 140, 0);
        else if (r.s.role == "default") dot(x, y, 6, 30, 90, 220);
        else if (r.s.role == "plain") dot(x, y, 6, 30, 160, 60);
        else if (r.pareto) dot(x, y, 4, 200, 30, 30);
        else dot(x, y, 3, 120, 120, 120);
    }
    return WritePng(path, f.w, f.h, img, error);
}

std::string PlotSvg(const std::vector<Row>& rows, const std::string& scene) {
    Frame f = MakeFrame(rows, scene);
    std::ostringstream s;
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << f.w << "\" height=\"" << f.h
      << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    s << "<text x=\"" << f.left << "\" y=\"18\" font-size=\"13\">" << Esc(scene)
      << ": GPU time against pixels more than 8/255 off a 4096-step render (red: Pareto front, blue: default, "
         "green: plain raymarcher; orange: render scales against the supersampled truth)</text>\n";
    for (int d = -3; d <= 2; ++d) {
        double y = f.Y(std::pow(10.0, d));
        s << "<line x1=\"" << f.left << "\" y1=\"" << y << "\" x2=\"" << f.w - f.right << "\" y2=\"" << y
          << "\" stroke=\"#ddd\"/><text x=\"" << f.left - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">"
          << F("%g", std::pow(10.0, d)) << "%</text>\n";
    }
    for (double v : XTicks(f)) {
        double x = f.X(v);
        s << "<line x1=\"" << x << "\" y1=\"" << f.top << "\" x2=\"" << x << "\" y2=\"" << f.h - f.bottom
          << "\" stroke=\"#eee\"/><text x=\"" << x << "\" y=\"" << f.h - f.bottom + 16 << "\" text-anchor=\"middle\">"
          << F("%g", v) << "</text>\n";
    }
    s << "<line x1=\"" << f.left << "\" y1=\"" << f.Y(0.1) << "\" x2=\"" << f.w - f.right << "\" y2=\"" << f.Y(0.1)
      << "\" stroke=\"#f0a0a0\" stroke-dasharray=\"4 3\"/>\n";
    s << "<text x=\"" << (f.w + f.left) / 2 << "\" y=\"" << f.h - 12 << "\" text-anchor=\"middle\">GPU ms per frame (log scale)</text>\n";
    s << "<text transform=\"translate(14," << (f.h / 2) << ") rotate(-90)\" text-anchor=\"middle\">% pixels &gt; 8/255 off</text>\n";
    for (bool scales : {false, true}) {
        s << "<polyline fill=\"none\" stroke=\"" << (scales ? "#e68c00" : "#c81e1e") << "\" stroke-width=\"1.5\" points=\"";
        for (const Row* r : Front(rows, scene, scales)) s << f.X(r->gpuMs) << "," << f.Y(r->img.pctOver8) << " ";
        s << "\"/>\n";
    }
    for (const Row& r : rows) {
        if (r.scene != scene) continue;
        const char* col = ScaleRow(r) ? "#e68c00" : r.s.role == "default" ? "#1e5adc" : r.s.role == "plain" ? "#1ea03c"
                        : r.pareto ? "#c81e1e" : "#888";
        int rad = r.s.role.empty() ? (r.pareto ? 4 : 3) : 6;
        s << "<circle cx=\"" << f.X(r.gpuMs) << "\" cy=\"" << f.Y(r.img.pctOver8) << "\" r=\"" << rad << "\" fill=\"" << col
          << "\"><title>" << Esc(r.s.label) << ": " << F("%.3f", r.gpuMs) << " ms, " << F("%.3f", r.img.pctOver8)
          << "% off</title></circle>\n";
        if (r.pareto || !r.s.role.empty())
            s << "<text x=\"" << f.X(r.gpuMs) + 7 << "\" y=\"" << f.Y(r.img.pctOver8) - 5 << "\" font-size=\"9\" fill=\"" << col
              << "\">" << Esc(r.s.label) << "</text>\n";
    }
    s << "</svg>\n";
    return s.str();
}

std::string MarkdownReport(const std::vector<Row>& rows, const SweepOptions& o, const SweepInfo& info,
                           const std::string& commandLine) {
    std::ostringstream m;
    const int rw = o.refWidth > 0 ? o.refWidth : o.width, rh = o.refHeight > 0 ? o.refHeight : o.height;
    m << "# Accuracy against time\n\n";
    if (info.wallClock)
        m << "> **Generated on llvmpipe (Mesa's software renderer), not on a GPU.** The error columns are what the GPU "
             "would give at this frame size; the times are a CPU rasterizer's wall clock on shared cores and are noisy "
             "(identical programs differ by 10-20 %). The GPU run replaces this file: `scripts/gpu.sh prepare`, then on the "
             "device (carrying .gl and .devbuild) `bash scripts/gpu.sh remote bench accuracy --scene all --size 1920x1080 "
             "--ref-size 960x540 --out $OUT/accuracy --markdown $OUT/docs/accuracy.md`, and commit docs/accuracy.md with "
             "docs/accuracy/.\n\n";
    m << "Generated by `" << commandLine << "` on **" << info.device << "** (" << info.path << " path; timing: "
      << (info.wallClock ? "glFinish + wall clock, software renderer: the times are llvmpipe's, not a GPU's"
                         : "GL_TIME_ELAPSED")
      << ", median of " << o.frames << " frames after " << o.warmup << " warm-up). Frame " << o.width << "x" << o.height
      << ", geometry compared at " << rw << "x" << rh << ", scene time " << o.time << " s, scene parameters at their defaults"
      << (o.params.empty() ? "" : " except the ones given") << ". CPU reference: " << F("%.1f", info.refSeconds) << " s.\n\n";
    m << "Re-generate: `" << commandLine << "` (CSV, plots and this file go to `--out`).\n\n";
    for (const auto& [scene, d] : info.drift) {
        double pct = d.first > 0 ? 100.0 * (d.second - d.first) / d.first : 0.0;
        m << "Drift check, " << scene << ": the first row timed alone " << F("%.3f", d.first) << " ms before the rounds and "
          << F("%.3f", d.second) << " ms after them (" << F("%+.1f", pct) << " %)"
          << (std::fabs(pct) > 3.0 ? ": **DRIFT over 3 %, this scene's times are not comparable**" : ", within 3 %") << ".\n\n";
    }
    m << "## How to read it\n\n"
         "Each row is one quality setting, everything else at sdfvj's defaults (`Quality` in `src/render/render.h`: "
         "128 steps, hit epsilon 1e-3 * max(1, t), step factor 1 divided by the scene's Lipschitz bound, central "
         "normals with offset 1e-3 * max(1, t), " << Quality{}.shadowSteps << " shadow steps with penumbra k = "
      << F("%g", Quality{}.shadowK) << ", " << Quality{}.aoSamples << " AO samples, the scene's bounding volume where it "
         "declares one), with the scene's own lighting (shadows, AO, specular, fog).\n\n"
         "- **ms**: GPU time per frame at the frame size, timed as `sdfvj bench` does. The settings are timed "
         "interleaved (each round draws every setting once, the median per setting is taken over the rounds), so GPU "
         "clock changes fall on all rows alike.\n"
         "- **% off**: pixels with any channel more than 8/255 away from a 4096-step render (1024 shadow steps, "
         "everything else at the defaults, central normals, same penumbra and AO samples and the same bounding-volume "
         "setting as the row), **PSNR** against "
         "it. This is the issue's image metric; it rewards convergence, not geometric truth (a smaller hit epsilon "
         "than the reference's 1e-3 can show as 'off'): the geometry columns measure truth.\n"
         "- Geometry against the **CPU double reference** (the same scene and render.glsl compiled as C++ in double, "
         "20000 steps, eps 1e-6 * max(1, t), step factor 0.5 / Lipschitz, the whole field without the bounding volume, normals by central differences at the "
         "default offset 1e-3 * max(1, t), which on smooth surfaces is within 1e-4 deg of the analytic normal and on the "
         "fractal fixes the scale the normal is taken at): **t err** = |t - t_ref| in pixel footprints "
         "(t * pixel angle), p50/p99 over pixels both hit; **sil** = % pixels where one hits and the other misses; "
         "**normal** = angle error in degrees, p50/p99; **oos** = % rays that ran out of steps (the renderer then "
         "calls them hits at the last position).\n"
         "- **plain** is a seed-style raymarcher: 128 steps, eps 1e-3, step factor 1 *not* divided by the Lipschitz "
         "bound (only the twisted, displaced `midi` scene has a bound above 1), marching the whole field everywhere "
         "(no bounding volume). **no bounding volume** is the default without the scene's bound (`BOUNDS 0`): what the "
         "bound buys. **fixed step** marches at a constant "
         "step and bisects the crossing. Rows marked P are on the Pareto front of (ms, % off).\n\n";
    m << "What each knob buys:\n\n"
         "- **max steps**: rays that graze a surface (floor at the horizon, silhouettes) creep and run out of steps; "
         "more steps fix them at the cost of time on exactly those rays.\n"
         "- **hit epsilon**: larger eps stops earlier (faster, surfaces shift by up to eps); smaller eps costs steps. "
         "*relative* (eps * max(1, t), the default), *fixed* (constant: far surfaces need many steps and below float "
         "resolution at distance it never triggers), *pixel* (eps in pixel footprints, t * pixel angle: uniform screen-space "
         "precision). The shadow and AO rays start 2 * eps off the surface, so eps also moves the shadow terminator: "
         "part of an eps row's image difference is that look change, not error (its geometry columns are the truth). "
         "Decoupling that offset from the hit epsilon would make eps a pure precision knob.\n"
         "- **normals**: central (6 map calls, second order), forward (4, first order), tetrahedron (4 map calls, first "
         "order too: see the normals section); offset trades "
         "noise against blurring of small features.\n"
         "- **shadow steps / penumbra**: shadow rays that run out of steps are counted as lit; k is a look, not a precision.\n"
         "- **AO samples**: the occlusion kernel; a look knob, compared with its own 4096-step render (the CSV's "
         "`pct_over_8_scene_look` also compares every row with the scene's own look: what `live --frame-budget` counts).\n"
         "- **step factor**: < 1 under-relaxes (safer on non-Lipschitz fields, more steps), > 1 over-relaxes (faster, "
         "oversteps thin parts).\n\n";
    std::vector<std::string> scenes;
    for (const Row& r : rows)
        if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end()) scenes.push_back(r.scene);
    // identical programs time alike on a GPU to ~1 %; llvmpipe's wall clock on shared cores is far noisier
    const double timeTolerance = info.wallClock ? 1.15 : 1.03;
    m << "## Where the default lands\n\nTarget (issue 6): at most 0.1 % of pixels more than 8/255 off, in no more time than "
         "the plain raymarcher (within " << F("%.0f", (timeTolerance - 1) * 100) << " % timing noise). On a scene with "
         "Lipschitz bound 1 and no bounding volume the default and plain rows are the same program. Penumbra and AO-samples rows "
         "are looks, not precision, and are never picked as the cheapest setting.\n\n"
         "| scene | plain ms | plain % off | default ms | default % off | default PSNR | target | cheapest setting with "
         "<= 0.1 % off |\n|---|---:|---:|---:|---:|---:|---|---|\n";
    for (const std::string& sc : scenes) {
        const Row *def = nullptr, *plain = nullptr, *best = nullptr;
        for (const Row& r : rows) {
            if (r.scene != sc) continue;
            if (r.s.role == "default") def = &r;
            if (r.s.role == "plain") plain = &r;
            if (!LookKnob(r) && r.img.pctOver8 <= 0.1 && (!best || r.gpuMs < best->gpuMs)) best = &r;
        }
        if (!def || !plain) continue;
        bool ok = def->img.pctOver8 <= 0.1 && def->gpuMs <= plain->gpuMs * timeTolerance;
        m << "| " << sc << " | " << F("%.3f", plain->gpuMs) << " | " << F("%.3f", plain->img.pctOver8) << " | "
          << F("%.3f", def->gpuMs) << " | " << F("%.3f", def->img.pctOver8) << " | " << F("%.1f", def->img.psnr) << " | "
          << (ok ? "met" : "**missed**") << " | "
          << (best ? best->s.label + " (" + F("%.3f", best->gpuMs) + " ms, " + F("%.3f", best->img.pctOver8) + " %)" : "none")
          << " |\n";
    }
    if (!info.boundEffect.empty()) {
        m << "\nThe bounding volume (scenes that declare one: a primary ray marches only inside the scene's bounding "
             "sphere and meets the ground analytically; a shadow ray marches only where the sphere can darken its "
             "penumbra) is a shortcut, not an approximation: `stability: marching inside the scene's bound...` checks on "
             "the CPU that it lands on the same surfaces. Its 4096-step render against the one without it:";
        for (const auto& [sc, d] : info.boundEffect)
            m << " `" << sc << "` " << F("%.3f", d.pctOver8) << " % off (" << F("%.1f", d.psnr) << " dB);";
        m << " these are the floor near the horizon, where the whole-field march stops up to eps * t / |rd.y| short of "
             "the plane (on grazing rays that shifts the checker and grid lines by whole pixels) while the bound meets it "
             "exactly, and on the fractal distance *estimate* a march that starts at the sphere instead of the camera "
             "stopping on different sub-pixel detail. The geometry columns (t err against the CPU truth) show the bounded "
             "rows at least as close as the unbounded ones.\n";
    }
    // One setting for every scene: the default candidates that meet the target everywhere.
    {
        std::vector<std::string> labels;
        for (const Row& r : rows)
            if (r.s.role != "plain" && !LookKnob(r) && std::find(labels.begin(), labels.end(), r.s.label) == labels.end())
                labels.push_back(r.s.label);
        std::string best;
        double bestCost = 1e30;
        std::string table;
        for (const std::string& label : labels) {
            bool all = true;
            double cost = 0;
            std::string cells;
            for (const std::string& sc : scenes) {
                const Row *r = nullptr, *plain = nullptr;
                for (const Row& x : rows) {
                    if (x.scene != sc) continue;
                    if (x.s.label == label) r = &x;
                    if (x.s.role == "plain") plain = &x;
                }
                if (!r || !plain) { all = false; break; }
                bool ok = r->img.pctOver8 <= 0.1 && r->gpuMs <= plain->gpuMs * timeTolerance;
                all = all && ok;
                cost += r->gpuMs / std::max(plain->gpuMs, 1e-9);
                cells += " " + F("%.3f", r->gpuMs / std::max(plain->gpuMs, 1e-9)) + "x, " + F("%.3f", r->img.pctOver8) + " %" +
                         (ok ? "" : " (no)") + " |";
            }
            if (all && cost < bestCost) { bestCost = cost; best = label; }
            if (all || label.find("shadow steps") != std::string::npos || label == "sdfvj default")
                table += "| " + label + " |" + cells + "\n";
        }
        m << "\n## One setting for every scene\n\nSettings that meet the target on every scene (time relative to the "
             "plain raymarcher, % off), plus the default and the shadow-step rows:\n\n| setting |";
        for (const std::string& sc : scenes) m << " " << sc << " |";
        m << "\n|---|";
        for (size_t i = 0; i < scenes.size(); ++i) m << "---|";
        m << "\n" << table << "\n"
          << (best.empty() ? std::string("No single setting of this sweep meets the target on every scene.\n")
                           : "Cheapest setting that meets the target on every scene: **" + best +
                                 "** (mean time " + F("%.3f", bestCost / scenes.size()) + "x the plain raymarcher's).\n");
    }
    m << "\n## Cheapest setting per error budget\n\n| scene | <= 1 % off | <= 0.5 % off | <= 0.1 % off | <= 0.01 % off |\n|---|---|---|---|---|\n";
    for (const std::string& sc : scenes) {
        m << "| " << sc << " |";
        for (double budget : {1.0, 0.5, 0.1, 0.01}) {
            const Row* best = nullptr;
            for (const Row& r : rows)
                if (r.scene == sc && !LookKnob(r) && r.img.pctOver8 <= budget && (!best || r.gpuMs < best->gpuMs)) best = &r;
            m << " " << (best ? best->s.label + " (" + F("%.3f", best->gpuMs) + " ms)" : "none") << " |";
        }
        m << "\n";
    }
    m << "\n## Normals: central, forward and tetrahedron against analytic normals\n\n"
         "Seed 002 claims the tetrahedron normal (4 map calls) is as accurate as central differences (6). Measured on "
         "2000 random surface points each (box: faces, 0.05 away from edges), angle to the analytic normal in degrees "
         "(the renderer's offset is u_normalEps * max(1, t), so 1e-3 at t = 1, 1e-2 at t = 10):\n\n"
      << NormalStatsMarkdown(MeasureNormals(2000))
      << "\nThe claim does not hold in general: the tetrahedron estimator is only first-order accurate. Its "
         "second-order term is sum_i k_i (k_i^T H k_i) for the Hessian H, and for the corners (+-1, +-1, +-1) with an "
         "even number of minus signs the mixed terms k_x k_y k_z do not cancel, so its error grows linearly with the "
         "offset, like forward differences (in double at offset 1e-3: sphere 0.028 deg, torus 0.12 deg, against "
         "central's 1e-5 deg). All three are exact on planar faces. At the renderer's default offset in float, the "
         "rounding of the distance dominates central differences, and all three methods stay below about 0.15 deg; "
         "at offset 1e-2 (distance 10 with the default 1e-3 * max(1, t)) tetrahedron and forward reach about 1 deg "
         "on the torus while central stays at 0.02 deg. Where the image shows it, see the normals rows of each "
         "scene below.\n\n"
         "So the renderer samples the first-order estimators at a tenth of the normal offset (render.glsl "
         "surfaceNormal; a normals row's label gives the offset sampled), where they match central's error with 4 "
         "map() calls instead of 6, and a scene may choose one in its header (EFFECTS \"NORMALS\"): every shipped "
         "scene but mandelbulb takes the tetrahedron, their default rows below use it (NVIDIA H200, session 9: normal p99 "
         "no worse than central's at 1e-3 in the same run, character's frame 11 % shorter; docs/performance.md). "
         "The fractal keeps central: its offset sets the scale of the detail it shades.\n";
    for (const std::string& sc : scenes) {
        m << "\n## " << sc << "\n\n![" << sc << "](accuracy/accuracy_" << sc << ".svg)\n\n";
        m << "| knob | setting | ms | % off | PSNR dB | t err p50 / p99 / max px | sil % | normal p50 / p99 deg | oos % | P |\n"
             "|---|---|---:|---:|---:|---|---:|---|---:|:-:|\n";
        for (const Row& r : rows) {
            if (r.scene != sc) continue;
            std::string label = r.s.role.empty() ? r.s.label : "**" + r.s.label + "**";
            m << "| " << r.s.knob << " | " << label << " | " << F("%.3f", r.gpuMs) << " | " << F("%.3f", r.img.pctOver8)
              << " | " << F("%.1f", r.img.psnr) << " | " << F("%.3g", r.g.tErrP50) << " / " << F("%.3g", r.g.tErrP99)
              << " / " << F("%.3g", r.g.tErrMax) << " | " << F("%.3f", r.g.silhouettePct) << " | "
              << F("%.3g", r.g.normalP50) << " / " << F("%.3g", r.g.normalP99) << " | " << F("%.2f", r.g.outOfStepsPct)
              << " | " << (r.pareto ? "P" : "") << " |\n";
        }
        if (std::any_of(rows.begin(), rows.end(), [&](const Row& r) { return r.scene == sc && r.s.knob == "scale"; }))
            m << "\nThe scale rows draw the default at that fraction of the size, resampled to it with a linear blit "
                 "(as `live --render-scale` shows them; 2x2 supersampled above 1), and are compared with the supersampled "
                 "truth: the 4096-step render at twice the size, averaged 2x2. Their % off is the resolution term of "
                 "`live --frame-budget`'s error; their geometry columns are the default's (a scale changes which rays are "
                 "cast, not how each is marched), and they form a Pareto front of their own.\n";
        if (sc == "mandelbulb")
            m << "\nOn the Mandelbulb the normal columns measure the fractal, not the renderer: its distance estimate's "
                 "gradient turns by about 40 deg (median) between offsets 1e-6 and 1e-3 and between the depth eps * t "
                 "where a ray stops and the surface, while the float and double builds agree to 0.002 deg at the same "
                 "point and offset. Read the image columns there.\n";
        for (const Row& r : rows)
            if (r.scene == sc && r.s.role == "default" && r.g.refOutOfStepsPct > 0)
                m << "\nThe CPU reference itself ran out of steps on " << F("%.3f", r.g.refOutOfStepsPct) << " % of pixels.\n";
    }
    return m.str();
}

}  // namespace sdfvj::accuracy
