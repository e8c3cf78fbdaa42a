// The quality sweep: each setting timed on the GPU and compared with the references.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <tuple>

#include "accuracy/accuracy.h"

namespace sdfvj::accuracy {

namespace {

const auto Fmt = Format;

Setting Make(const std::string& knob, const std::string& label) {
    Setting s;
    s.knob = knob;
    s.label = label;
    return s;
}

}  // namespace

std::vector<Setting> SweepSettings(const std::string& which) {
    std::vector<Setting> out;
    Setting def = Make("default", "sdfvj default");
    def.role = "default";
    out.push_back(def);
    // The seed-style raymarcher: 128 steps, eps 1e-3, step factor 1 NOT divided by the scene's
    // Lipschitz bound (the sweep multiplies the bound back in for this row).
    Setting plain = Make("plain", "plain (128 steps, eps 1e-3, factor 1, no Lipschitz, no bound)");
    plain.role = "plain";
    plain.naiveStep = true;
    plain.bounds = false;
    plain.q.conePrepass = false;
    out.push_back(plain);
    // What the scene's bounding volume buys: the defaults marching the whole field everywhere.
    Setting unbounded = Make("bounds", "no bounding volume");
    unbounded.bounds = false;
    out.push_back(unbounded);
    // What the compute path's cone pre-pass buys: the defaults with every primary ray from the eye.
    Setting noCone = Make("cone", "no cone pre-pass");
    noCone.q.conePrepass = false;
    out.push_back(noCone);
    // Render scales, each at the default quality (`live --render-scale` and the frame budget's
    // resolution term): fewer pixels upscaled, or 2x2 supersampled.
    auto scales = [&](std::initializer_list<float> list) {
        for (float f : list) {
            Setting s = Make("scale", f > 1.0f ? "supersampled 2x2" : "scale=" + Fmt("%.2f", f));
            s.scale = f;
            out.push_back(s);
        }
    };
    if (which == "scale") {
        scales({0.25f, 0.33f, 0.5f, 0.7f, 0.85f, 1.0f, 2.0f});
        return out;
    }
    auto aoSamples = [&] {
        for (int n : {1, 2, 3, 8, 16}) {
            Setting s = Make("ao_samples", "ao samples=" + std::to_string(n));
            s.q.aoSamples = n;
            out.push_back(s);
        }
    };
    auto penumbrae = [&] {
        for (double k : {4.0, 16.0, 32.0}) {
            Setting s = Make("penumbra", "shadow k=" + Fmt("%g", k));
            s.q.shadowK = (float)k;
            out.push_back(s);
        }
    };
    if (which == "looks") {   // the look rows (penumbra, AO samples), with their distance from the scene's look
        penumbrae();
        aoSamples();
        return out;
    }
    if (which == "tiny") {
        Setting s = Make("steps", "steps=32");
        s.q.maxSteps = 32;
        out.push_back(s);
        s = Make("eps_pixel", "eps=1px");
        s.epsMode = 2;
        s.q.hitEps = 1.0f;
        out.push_back(s);
        s = Make("normals", "tetrahedron eps=1e-4");   // a tenth of central's offset (render.glsl)
        s.normals = 2;
        out.push_back(s);
        s = Make("fixed_step", "fixed step 0.1");
        s.marchFixed = true;
        s.q.fixedStep = 0.1f;
        s.q.maxSteps = 500;
        out.push_back(s);
        return out;
    }
    // What over-relaxed sphere tracing buys (render/march.glsl OVERRELAX, on where the field is a
    // distance bound): the defaults with plain sphere tracing.
    Setting plainTrace = Make("overrelax", "plain sphere tracing (no over-relaxation)");
    plainTrace.defines = {"OVERRELAX 0"};
    out.push_back(plainTrace);
    for (int n : {16, 32, 64, 96, 128, 192, 256, 512, 1024}) {
        Setting s = Make("steps", "steps=" + std::to_string(n));
        s.q.maxSteps = n;
        out.push_back(s);
    }
    for (double e : {1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 1e-5, 1e-6}) {
        Setting s = Make("eps_relative", "eps=" + Fmt("%g", e) + "*max(1,t)");
        s.q.hitEps = (float)e;
        out.push_back(s);
    }
    for (double e : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
        Setting s = Make("eps_fixed", "eps=" + Fmt("%g", e) + " fixed");
        s.q.hitEps = (float)e;
        s.epsMode = 1;
        out.push_back(s);
    }
    for (double e : {4.0, 2.0, 1.0, 0.5, 0.25, 0.1}) {
        Setting s = Make("eps_pixel", "eps=" + Fmt("%g", e) + "px");
        s.q.hitEps = (float)e;
        s.epsMode = 2;
        out.push_back(s);
    }
    const char* methods[] = {"central", "forward", "tetrahedron"};
    for (int m = 0; m < 3; ++m)
        for (double e : {1e-2, 1e-3, 1e-4}) {
            // The label is the offset sampled: the first-order methods sample at a tenth of
            // u_normalEps (render.glsl surfaceNormal).
            Setting s = Make("normals", std::string(methods[m]) + " eps=" + Fmt("%g", e));
            s.normals = m;
            s.q.normalEps = (float)(m == 0 ? e : 10 * e);
            out.push_back(s);
        }
    for (int n : {8, 16, 24, 32, 40, 48, 64, 128, 256}) {
        Setting s = Make("shadow_steps", "shadow steps=" + std::to_string(n));
        s.q.shadowSteps = n;
        out.push_back(s);
    }
    penumbrae();
    aoSamples();
    for (double f : {0.5, 0.6, 0.7, 0.8, 0.9, 1.1, 1.25, 1.5}) {
        Setting s = Make("step_factor", "step factor=" + Fmt("%g", f));
        s.q.stepFactor = (float)f;
        out.push_back(s);
    }
    for (double st : {0.2, 0.1, 0.05, 0.02}) {
        Setting s = Make("fixed_step", "fixed step " + Fmt("%g", st));
        s.marchFixed = true;
        s.q.fixedStep = (float)st;
        s.q.maxSteps = std::min(4096, (int)std::ceil(s.q.maxDist / st));
        out.push_back(s);
    }
    scales({0.25f, 0.33f, 0.5f, 0.7f, 0.85f, 1.0f, 2.0f});
    // Combinations a default could move to.
    struct Combo { int steps; int epsMode; float eps; float factor; int shadowSteps; };
    for (Combo c : {Combo{192, 0, 1e-3f, 1.0f, 64}, Combo{256, 0, 1e-3f, 1.0f, 64}, Combo{128, 2, 0.5f, 1.0f, 64},
                    Combo{192, 2, 0.5f, 1.0f, 64}, Combo{256, 2, 1.0f, 1.0f, 64}, Combo{256, 0, 3e-4f, 0.9f, 64},
                    Combo{128, 0, 1e-3f, 1.0f, 32}, Combo{160, 0, 1e-3f, 1.0f, 32}, Combo{192, 0, 1e-3f, 1.0f, 32},
                    Combo{192, 0, 1e-3f, 1.0f, 24}, Combo{256, 0, 1e-3f, 1.0f, 16}, Combo{128, 0, 1e-3f, 1.0f, 48},
                    Combo{160, 0, 1e-3f, 1.0f, 48}, Combo{192, 0, 1e-3f, 1.0f, 48}}) {
        Setting s = Make("combo", "steps=" + std::to_string(c.steps) + " eps=" + Fmt("%g", c.eps) +
                                      (c.epsMode == 2 ? "px" : "*max(1,t)") + " factor=" + Fmt("%g", c.factor) +
                                      " shadow steps=" + std::to_string(c.shadowSteps));
        s.q.maxSteps = c.steps;
        s.epsMode = c.epsMode;
        s.q.hitEps = c.eps;
        s.q.stepFactor = c.factor;
        s.q.shadowSteps = c.shadowSteps;
        out.push_back(s);
    }
    return out;
}

bool RunSweep(const SweepOptions& o, std::vector<Row>* rows, SweepInfo* info, std::string* error) {
    auto log = [&](const std::string& s) { if (o.log) o.log(s); };
    info->wallClock = IsSoftwareRenderer();
    info->device = GlRendererName();
    const int rw = o.refWidth > 0 ? o.refWidth : o.width;
    const int rh = o.refHeight > 0 ? o.refHeight : o.height;
    std::vector<Setting> settings = SweepSettings(o.sweep);
    FrameRenderer colour, geom;
    for (const std::string& name : o.scenes) {
        SceneInfo scene;
        if (!FindScene(name, &scene, error)) return false;
        if (!HasCpuScene(scene.name)) {
            std::string known;
            for (const auto& n : CpuSceneNames()) known += (known.empty() ? "" : ", ") + n;
            *error = "no CPU reference build of scene '" + scene.name + "', expected one of " + known +
                     " (a scene file added since the last cmake configure needs a rebuild)";
            return false;
        }
        RenderPath path = o.path == "compute" ? RenderPath::Compute : o.path == "fragment" ? RenderPath::Fragment
                                                                                          : ProbeRenderPath(scene, nullptr);
        info->path = RenderPathName(path);
        FrameInputs base;
        base.time = o.time;
        base.frame = 0;
        for (const ParamDecl& d : scene.params) base.params.emplace_back(d.name, d.defaultValue);
        for (const auto& [n, v] : o.params)
            for (auto& [bn, bv] : base.params)
                if (bn == n) bv = v;

        // CPU double reference geometry.
        auto t0 = std::chrono::steady_clock::now();
        Geometry ref = CpuReferenceGeometry(scene, base, rw, rh, ReferenceSettings{}, o.threads);
        double refS = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        info->refSeconds += refS;
        log(scene.name + ": CPU double reference " + std::to_string(rw) + "x" + std::to_string(rh) + " in " +
            Fmt("%.1f", refS) + " s");
        // The plain raymarcher marches the raw field: scenes that divide a non-Lipschitz part by
        // its own bound (midi) have a SCENE_GLOBAL_LIPSCHITZ build that leaves it raw.
        const bool hasRaw = HasGlobalLipschitzBuild(scene.name);
        double lipschitz = 1.0;
        {
            CpuScene<float> s32 = MakeCpuSceneGlobal32(scene.name);
            ApplyFrame(s32, scene, base, rw, rh);
            lipschitz = std::max(1.0, (double)s32.lipschitz());
        }

        std::map<std::string, std::unique_ptr<Program>> programs;
        auto program = [&](const EffectSet& e, int epsMode, Program** out, bool raw = false, bool bounds = true,
                           const std::vector<std::string>& extra = {}) {
            std::string key = DescribeEffects(e) + "|n" + std::to_string(e.normals) + "|f" + std::to_string(e.marchFixed) +
                              "|d" + std::to_string(e.debugView) + "|e" + std::to_string(epsMode) + (raw ? "|raw" : "") +
                              (bounds ? "" : "|unbounded");
            for (const std::string& d : extra) key += "|" + d;
            auto it = programs.find(key);
            if (it == programs.end()) {
                auto p = std::make_unique<Program>();
                std::vector<std::string> defines = {"EPS_MODE " + std::to_string(epsMode)};
                if (raw) defines.push_back("SCENE_GLOBAL_LIPSCHITZ 1");
                if (!bounds) defines.push_back("BOUNDS 0");
                defines.insert(defines.end(), extra.begin(), extra.end());
                if (!BuildProgram(scene, e, path, defines, p.get(), error)) return false;
                it = programs.emplace(key, std::move(p)).first;
            }
            *out = it->second.get();
            return true;
        };

        // High-quality GPU images, one per look (penumbra and AO samples change the look) and per
        // BOUNDS setting.
        // The reference: the same renderer with 4096 steps (and 1024 shadow steps),
        // everything else at the defaults but the look; geometric truth is the CPU reference's job.
        auto hqProgram = [&](const Quality& look, bool bounds, FrameInputs* in, Program** p) {
            *in = base;
            in->quality = Quality{};
            in->quality.conePrepass = false;   // every ray from the eye, as a plain raymarcher
            in->quality.maxSteps = 4096;
            in->quality.shadowSteps = 1024;
            in->quality.shadowK = look.shadowK;
            in->quality.aoSamples = look.aoSamples;
            EffectSet e = scene.effects;
            e.normals = 0;
            e.marchFixed = false;
            return program(e, 0, p, false, bounds);
        };
        std::map<std::tuple<float, int, bool>, std::vector<uint8_t>> hq;
        auto hqImage = [&](const Quality& look, bool bounds, std::vector<uint8_t>** out) {
            auto key = std::make_tuple(look.shadowK, look.aoSamples, bounds);
            auto it = hq.find(key);
            if (it == hq.end()) {
                FrameInputs in;
                Program* p = nullptr;
                if (!hqProgram(look, bounds, &in, &p)) return false;
                if (!colour.Resize(o.width, o.height, error)) return false;
                colour.Draw(*p, scene, in, false);
                it = hq.emplace(key, colour.ReadPixels()).first;
            }
            *out = &it->second;
            return true;
        };
        if (MakeCpuScene32(scene.name).hasBound) {
            std::vector<uint8_t>*with = nullptr, *without = nullptr;
            if (!hqImage(Quality{}, true, &with) || !hqImage(Quality{}, false, &without)) return false;
            info->boundEffect[scene.name] = CompareRgba8(*with, *without);
        }

        // Render scales: a target per scale, resampled to the sweep's size with a linear blit (what
        // `live --render-scale` shows), and compared with the supersampled truth.
        std::map<int, std::unique_ptr<FrameRenderer>> scaledTargets;   // by round(scale x 1000)
        FrameRenderer resampled;
        auto side = [](int n, float s) { return std::max(1, (int)std::lround(n * s)); };
        auto scaledTarget = [&](float s, FrameRenderer** out) {
            auto& t = scaledTargets[(int)std::lround(s * 1000.0f)];
            if (!t) t = std::make_unique<FrameRenderer>();
            if (!t->Resize(side(o.width, s), side(o.height, s), error)) return false;
            *out = t.get();
            return true;
        };
        auto resample = [&](const FrameRenderer& from, float s, std::vector<uint8_t>* img) {
            if (!resampled.Resize(o.width, o.height, error)) return false;
            const int fw = side(o.width, s), fh = side(o.height, s);
            glBindFramebuffer(GL_READ_FRAMEBUFFER, from.Framebuffer());
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resampled.Framebuffer());
            glBlitFramebuffer(0, 0, fw, fh, 0, 0, o.width, o.height, GL_COLOR_BUFFER_BIT,
                              fw == o.width && fh == o.height ? GL_NEAREST : GL_LINEAR);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            *img = resampled.ReadPixels();
            return true;
        };
        std::vector<uint8_t> ssTruth;   // the 4096-step render at 2x2 the size, averaged (on first use)
        auto supersampledTruth = [&](std::vector<uint8_t>** out) {
            if (ssTruth.empty()) {
                FrameInputs in;
                Program* p = nullptr;
                FrameRenderer* big = nullptr;
                if (!hqProgram(Quality{}, true, &in, &p) || !scaledTarget(2.0f, &big)) return false;
                big->Draw(*p, scene, in, false);
                if (!resample(*big, 2.0f, &ssTruth)) return false;
            }
            *out = &ssTruth;
            return true;
        };

        // Accuracy first (deterministic), one setting after another.
        struct Timed { Program* program; FrameInputs in; size_t row; std::vector<double> ms; FrameRenderer* target; };
        std::vector<Timed> timed;
        GeometryError defaultGeometry;
        for (const Setting& st : settings) {
            FrameInputs in = base;
            in.quality = st.q;
            if (st.naiveStep) in.quality.stepFactor = (float)(st.q.stepFactor * lipschitz);
            EffectSet e = scene.effects;
            if (st.normals >= 0) e.normals = st.normals;
            e.marchFixed = st.marchFixed;
            const bool raw = st.naiveStep && hasRaw;
            Program* shaded = nullptr;
            if (!program(e, st.epsMode, &shaded, raw, st.bounds, st.defines)) return false;
            if (st.knob == "scale") {
                FrameRenderer* target = nullptr;
                std::vector<uint8_t> img, *truth = nullptr;
                if (!scaledTarget(st.scale, &target)) return false;
                target->Draw(*shaded, scene, in, false);
                if (!resample(*target, st.scale, &img) || !supersampledTruth(&truth)) return false;
                Row r;
                r.scene = scene.name;
                r.s = st;
                r.s.normals = e.normals;
                r.img = CompareRgba8(img, *truth);
                r.imgSceneLook = r.img;
                r.g = defaultGeometry;
                timed.push_back({shaded, in, rows->size(), {}, target});
                rows->push_back(r);
                continue;
            }
            if (!colour.Resize(o.width, o.height, error)) return false;
            colour.Draw(*shaded, scene, in, false);
            Row r;
            r.scene = scene.name;
            r.s = st;
            r.s.normals = e.normals;   // what was drawn: the scene's method on its default row
            std::vector<uint8_t> img = colour.ReadPixels();
            std::vector<uint8_t>* ref8 = nullptr;
            if (!hqImage(st.q, st.bounds, &ref8)) return false;
            r.img = CompareRgba8(img, *ref8);
            std::vector<uint8_t>* look8 = nullptr;
            if (!hqImage(Quality{}, st.bounds, &look8)) return false;
            r.imgSceneLook = look8 == ref8 ? r.img : CompareRgba8(img, *look8);

            EffectSet eg = e;
            eg.debugView = 4;
            Program* gp = nullptr;
            if (!program(eg, st.epsMode, &gp, raw, st.bounds, st.defines)) return false;
            if (!geom.Resize(rw, rh, error, true)) return false;
            geom.Draw(*gp, scene, in, false);
            Geometry g = DecodeGeometry(geom.ReadPixelsFloat(), rw, rh);
            r.g = CompareGeometry(g, ref, PixelAngle(scene, rh));
            if (st.role == "default") defaultGeometry = r.g;
            timed.push_back({shaded, in, rows->size(), {}, &colour});
            rows->push_back(r);
        }

        // Then time every setting interleaved: each round draws every setting once, so a GPU
        // clock change lands on all of them alike instead of on whichever rows ran during it.
        if (!colour.Resize(o.width, o.height, error)) return false;
        // The GPU idled while the CPU reference ran and waited on every compile above, so its
        // clocks are down: keep it busy for a second, drawing every setting, before timing, or
        // the first rows read up to 3x too slow.
        {
            const auto w0 = std::chrono::steady_clock::now();
            do {
                for (Timed& t : timed) t.target->Draw(*t.program, scene, t.in, false);
                glFinish();
            } while (std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count() < 1.0);
        }
        auto timeFirst = [&] {
            std::vector<double> ms;
            for (int i = 0; i < std::max(o.frames, 1); ++i) {
                timed[0].target->Draw(*timed[0].program, scene, timed[0].in, true);
                ms.push_back(timed[0].target->LastGpuMs());
            }
            return MedianMs(ms);
        };
        const double driftStart = timeFirst();
        for (int i = 0; i < o.warmup + o.frames; ++i)
            for (Timed& t : timed) {
                t.target->Draw(*t.program, scene, t.in, true);
                if (i >= o.warmup) t.ms.push_back(t.target->LastGpuMs());
            }
        info->drift[scene.name] = {driftStart, timeFirst()};
        for (Timed& t : timed) {
            Row& r = (*rows)[t.row];
            r.gpuMs = MedianMs(t.ms);
            char line[512];
            std::snprintf(line, sizeof line,
                          "%s | %-44s | %8.3f ms | %6.3f%% >8/255, %5.1f dB | t err p50 %.3g p99 %.3g px | sil %.3f%% | "
                          "normal p50 %.3g p99 %.3g deg | out of steps %.2f%%",
                          scene.name.c_str(), r.s.label.c_str(), r.gpuMs, r.img.pctOver8, r.img.psnr, r.g.tErrP50,
                          r.g.tErrP99, r.g.silhouettePct, r.g.normalP50, r.g.normalP99, r.g.outOfStepsPct);
            log(line);
        }
    }
    MarkPareto(rows);
    return true;
}

void MarkPareto(std::vector<Row>* rows) {
    for (Row& a : *rows) {
        a.pareto = true;
        for (const Row& b : *rows) {
            if (&a == &b || b.scene != a.scene || (a.s.knob == "scale") != (b.s.knob == "scale")) continue;
            bool noWorse = b.gpuMs <= a.gpuMs && b.img.pctOver8 <= a.img.pctOver8;
            bool better = b.gpuMs < a.gpuMs || b.img.pctOver8 < a.img.pctOver8;
            if (noWorse && better) { a.pareto = false; break; }
        }
    }
}

}  // namespace sdfvj::accuracy
