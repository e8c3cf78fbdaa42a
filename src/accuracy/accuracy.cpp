// CPU scenes, the CPU reference geometry, geometry read-back and the error metrics.
#include "accuracy/accuracy.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <stdexcept>
#include <thread>

namespace sdfvj::accuracy {

std::string Format(const char* format, double v) {
    char b[64];
    std::snprintf(b, sizeof b, format, v);
    return b;
}

std::vector<std::string> CpuSceneNames() {
    std::vector<std::string> names;
    for (const CpuSceneBuild& b : CpuSceneBuilds()) names.push_back(b.name);
    return names;
}

static const CpuSceneBuild* FindCpuScene(const std::string& name) {
    for (const CpuSceneBuild& b : CpuSceneBuilds())
        if (b.name == name) return &b;
    return nullptr;
}

bool HasCpuScene(const std::string& name) { return FindCpuScene(name) != nullptr; }

bool HasGlobalLipschitzBuild(const std::string& name) {
    const CpuSceneBuild* b = FindCpuScene(name);
    return b && b->makeGlobal32;
}

// A programmer bug, not bad input: every caller asks HasCpuScene() first (the bench reports an
// unknown scene to the user as a value). Says which name and stops.
[[noreturn]] static void UnknownCpuScene(const std::string& name) {
    std::string known;
    for (const auto& n : CpuSceneNames()) known += (known.empty() ? "" : ", ") + n;
    std::fprintf(stderr, "sdfvj: bug: MakeCpuScene('%s') without HasCpuScene() first; CPU builds exist for %s "
                 "(a scene added since the last cmake configure needs one)\n", name.c_str(), known.c_str());
    std::abort();
}

CpuScene<float> MakeCpuScene32(const std::string& name) {
    if (const CpuSceneBuild* b = FindCpuScene(name)) return b->make32();
    UnknownCpuScene(name);
}
CpuScene<double> MakeCpuScene64(const std::string& name) {
    if (const CpuSceneBuild* b = FindCpuScene(name)) return b->make64();
    UnknownCpuScene(name);
}
CpuScene<float> MakeCpuSceneGlobal32(const std::string& name) {
    const CpuSceneBuild* b = FindCpuScene(name);
    if (!b) UnknownCpuScene(name);
    return b->makeGlobal32 ? b->makeGlobal32() : b->make32();
}
CpuScene<double> MakeCpuSceneGlobal64(const std::string& name) {
    const CpuSceneBuild* b = FindCpuScene(name);
    if (!b) UnknownCpuScene(name);
    return b->makeGlobal64 ? b->makeGlobal64() : b->make64();
}

void ParallelRows(int height, int threads, const std::function<void(int)>& f) {
    int n = threads > 0 ? threads : (int)std::max(1u, std::thread::hardware_concurrency());
    n = std::min(n, std::max(height, 1));
    std::vector<std::thread> pool;
    for (int k = 0; k < n; ++k)
        pool.emplace_back([&, k] {
            for (int y = k; y < height; y += n) f(y);
        });
    for (auto& t : pool) t.join();
}

double PixelAngle(const SceneInfo& scene, int height) {
    double fov = std::clamp((double)scene.fov, 1.0, 179.0) * M_PI / 180.0;
    return 2.0 * std::tan(0.5 * fov) / std::max(height, 1);
}

Geometry CpuReferenceGeometry(const SceneInfo& scene, const FrameInputs& in, int width, int height,
                              const ReferenceSettings& r, int threads) {
    CpuScene<double> s = MakeCpuScene64(scene.name);
    FrameInputs ref = in;
    ref.quality.maxSteps = r.maxSteps;
    ref.quality.hitEps = (float)r.hitEps;
    ref.quality.stepFactor = (float)r.stepFactor;
    ApplyFrame(s, scene, ref, width, height);
    *s.hitEps = r.hitEps;   // exactly, not through float
    *s.stepFactor = r.stepFactor;
    Geometry g;
    g.width = width;
    g.height = height;
    g.px.resize((size_t)width * height);
    const glm::dvec3 ro = *s.camPos;
    ParallelRows(height, threads, [&](int y) {
        for (int x = 0; x < width; ++x) {
            glm::dvec3 rd = s.cameraRay(glm::dvec2(x + 0.5, y + 0.5));
            CpuRay<double> h = s.marchWhole(ro, rd, 0.0);   // the truth takes no shortcut
            GeomPixel& p = g.px[(size_t)y * width + x];
            p.steps = (float)h.steps;
            p.hit = h.hit;
            if (h.hit) {
                glm::dvec3 q = ro + rd * h.t;
                p.outOfSteps = h.steps >= r.maxSteps && s.map(q).w >= s.hitEpsilon(h.t);
                p.t = (float)h.t;
                glm::dvec3 n = s.normalCentral(q, r.normalEps * std::max(1.0, h.t));
                for (int i = 0; i < 3; ++i) p.n[i] = (float)n[i];
            }
        }
    });
    return g;
}

Geometry DecodeGeometry(const std::vector<float>& rgba, int width, int height) {
    Geometry g;
    g.width = width;
    g.height = height;
    g.px.resize((size_t)width * height);
    for (size_t i = 0; i < g.px.size(); ++i) {
        const float* v = &rgba[i * 4];
        GeomPixel& p = g.px[i];
        p.hit = v[0] >= 0.0f;
        p.t = v[0];
        p.steps = std::floor(v[3]);
        p.outOfSteps = v[3] - p.steps > 0.25f;
        // octahedral decode
        float x = v[1], y = v[2], z = 1.0f - std::fabs(x) - std::fabs(y);
        if (z < 0.0f) {
            float ox = (1.0f - std::fabs(y)) * (x < 0.0f ? -1.0f : 1.0f);
            float oy = (1.0f - std::fabs(x)) * (y < 0.0f ? -1.0f : 1.0f);
            x = ox;
            y = oy;
        }
        float l = std::sqrt(x * x + y * y + z * z);
        if (l > 0.0f && std::isfinite(l)) { p.n[0] = x / l; p.n[1] = y / l; p.n[2] = z / l; }
        else { p.n[0] = p.n[1] = p.n[2] = NAN; }
    }
    return g;
}

namespace {
double Percentile(std::vector<double>& v, double q) {
    if (v.empty()) return 0.0;
    size_t k = std::min(v.size() - 1, (size_t)std::floor(q * (v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    return v[k];
}
}  // namespace

GeometryError CompareGeometry(const Geometry& test, const Geometry& ref, double pixelAngle) {
    GeometryError e;
    if (test.width != ref.width || test.height != ref.height || ref.px.empty()) return e;
    std::vector<double> terr, nerr;
    size_t mismatch = 0, oos = 0, refOos = 0;
    for (size_t i = 0; i < ref.px.size(); ++i) {
        const GeomPixel& a = test.px[i];
        const GeomPixel& b = ref.px[i];
        if (a.outOfSteps) ++oos;
        if (b.outOfSteps) ++refOos;
        if (a.hit != b.hit) { ++mismatch; continue; }
        if (!a.hit) continue;
        double tr = std::max((double)b.t, 1e-6);
        terr.push_back(std::fabs((double)a.t - b.t) / (tr * pixelAngle));
        double d = (double)a.n[0] * b.n[0] + (double)a.n[1] * b.n[1] + (double)a.n[2] * b.n[2];
        nerr.push_back(std::isfinite(d) ? std::acos(std::clamp(d, -1.0, 1.0)) * 180.0 / M_PI : 180.0);
    }
    const double n = (double)ref.px.size();
    e.bothHit = (int)terr.size();
    e.silhouettePct = 100.0 * mismatch / n;
    e.outOfStepsPct = 100.0 * oos / n;
    e.refOutOfStepsPct = 100.0 * refOos / n;
    e.tErrMax = terr.empty() ? 0.0 : *std::max_element(terr.begin(), terr.end());
    e.tErrP50 = Percentile(terr, 0.5);
    e.tErrP99 = Percentile(terr, 0.99);
    e.normalP50 = Percentile(nerr, 0.5);
    e.normalP99 = Percentile(nerr, 0.99);
    return e;
}

std::vector<uint8_t> DownsampleRgba8x2(const std::vector<uint8_t>& rgba, int w, int h) {
    const int ow = w / 2, oh = h / 2;
    std::vector<uint8_t> out(size_t(ow) * oh * 4);
    for (int y = 0; y < oh; ++y)
        for (int x = 0; x < ow; ++x)
            for (int c = 0; c < 4; ++c) {
                int sum = 0;
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) sum += rgba[(size_t(2 * y + dy) * w + 2 * x + dx) * 4 + c];
                out[(size_t(y) * ow + x) * 4 + c] = uint8_t((sum + 2) / 4);
            }
    return out;
}

ImageError CompareRgba8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    ImageError e;
    if (a.size() != b.size() || a.empty()) return e;
    double se = 0;
    size_t over = 0, pixels = a.size() / 4;
    for (size_t p = 0; p < pixels; ++p) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
            int d = std::abs((int)a[p * 4 + c] - (int)b[p * 4 + c]);
            se += (double)d * d;
            worst = std::max(worst, d);
        }
        if (worst > 8) ++over;
    }
    double mse = se / (3.0 * pixels);
    e.psnr = mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
    e.pctOver8 = 100.0 * over / pixels;
    return e;
}

size_t CountNonFinite(const std::vector<float>& v, size_t* firstBad) {
    size_t n = 0;
    for (size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i])) {
            if (n == 0 && firstBad) *firstBad = i / 4;
            ++n;
        }
    return n;
}

bool BuildProgram(const SceneInfo& scene, const EffectSet& effects, RenderPath path,
                  const std::vector<std::string>& extraDefines, Program* out, std::string* error) {
    ShaderSource src;
    if (!AssembleProgram(scene, VariantKey{scene.path, effects, path}, &src, error)) return false;
    if (!extraDefines.empty()) {
        size_t eol = src.text.find('\n');
        std::string defs;
        for (const auto& d : extraDefines) defs += "#define " + d + "\n";
        src.text.insert(eol + 1, defs);
        // keep file:line mapping of the first source string right: #line after our lines
        src.text.insert(eol + 1 + defs.size(), "#line 2 0\n");
        src.hash = HashBytes(src.text);
    }
    return out->Build(src, path, error);
}

}  // namespace sdfvj::accuracy
