// Normal estimators of lib/shading.glsl (central, forward, tetrahedron) against analytic
// normals of a sphere, a box and a torus, in the float (GPU-like) and double builds.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "accuracy/accuracy.h"

#define SDF_NORMALS_BODY                                                                   \
    static int g_shape = 0;                                                                \
    vec4 map(vec3 p) {                                                                     \
        float d = g_shape == 0   ? fSphere(p, 1.0f)                                        \
                  : g_shape == 1 ? fBox(p, vec3(1.0f, 0.6f, 0.8f))                         \
                                 : fTorus(p, 0.3f, 1.0f);                                  \
        return vec4(1.0f, 1.0f, 1.0f, d);                                                  \
    }                                                                                      \
    float sceneLipschitz() { return 1.0f; }

namespace sdfvj::accuracy {
namespace nrm32 {
namespace {
#define SDF_GLSL_DOUBLE 0
#include "sdf/glsl_prelude.h"
#include "lib/common.glsl"
#include "lib/primitives.glsl"
SDF_NORMALS_BODY
#include "lib/shading.glsl"
#undef SDF_GLSL_DOUBLE
#undef uniform
}  // namespace
}  // namespace nrm32
namespace nrm64 {
namespace {
#define SDF_GLSL_DOUBLE 1
#include "sdf/glsl_prelude.h"
#define float double
#include "lib/common.glsl"
#include "lib/primitives.glsl"
SDF_NORMALS_BODY
#include "lib/shading.glsl"
#undef float
#undef SDF_GLSL_DOUBLE
#undef uniform
}  // namespace
}  // namespace nrm64

namespace {

// A random point on the surface of shape s and its analytic normal (double).
void SurfacePoint(int shape, std::mt19937& rng, glm::dvec3* p, glm::dvec3* n) {
    std::normal_distribution<double> g(0.0, 1.0);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    if (shape == 0) {
        glm::dvec3 d = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
        *p = d;
        *n = d;
    } else if (shape == 1) {
        // a face point at least 0.05 from every edge (the normal is undefined on edges)
        const glm::dvec3 b(1.0, 0.6, 0.8);
        int axis = std::uniform_int_distribution<int>(0, 2)(rng);
        double side = u(rng) < 0 ? -1.0 : 1.0;
        glm::dvec3 q;
        for (int i = 0; i < 3; ++i) q[i] = u(rng) * (b[i] - 0.05);
        q[axis] = side * b[axis];
        *p = q;
        *n = glm::dvec3(0.0);
        (*n)[axis] = side;
    } else {
        double a = std::uniform_real_distribution<double>(0.0, 2.0 * M_PI)(rng);
        double b = std::uniform_real_distribution<double>(0.0, 2.0 * M_PI)(rng);
        glm::dvec3 ring(std::cos(a), 0.0, std::sin(a));
        glm::dvec3 dir = std::cos(b) * ring + glm::dvec3(0.0, std::sin(b), 0.0);
        *p = ring * 1.0 + dir * 0.3;
        *n = dir;
    }
}

double Pct(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, (size_t)(q * (v.size() - 1) + 0.5))];
}

}  // namespace

std::vector<NormalStats> MeasureNormals(int samples) {
    std::vector<NormalStats> out;
    const char* shapes[] = {"sphere", "box", "torus"};
    const char* methods[] = {"central", "forward", "tetrahedron"};
    for (int dbl = 0; dbl < 2; ++dbl)
        for (int shape = 0; shape < 3; ++shape)
            for (double eps : {1e-2, 1e-3, 1e-4})
                for (int m = 0; m < 3; ++m) {
                    nrm32::g_shape = shape;
                    nrm64::g_shape = shape;
                    std::mt19937 rng(1234 + shape);
                    std::vector<double> err;
                    size_t bad = 0;
                    for (int i = 0; i < samples; ++i) {
                        glm::dvec3 p, n;
                        SurfacePoint(shape, rng, &p, &n);
                        glm::dvec3 e;
                        if (dbl) {
                            e = m == 0 ? nrm64::calcNormalCentral(p, eps) : m == 1 ? nrm64::calcNormalForward(p, eps)
                                                                                   : nrm64::calcNormalTetra(p, eps);
                        } else {
                            glm::vec3 pf(p), r = m == 0 ? nrm32::calcNormalCentral(pf, (float)eps)
                                               : m == 1 ? nrm32::calcNormalForward(pf, (float)eps)
                                                        : nrm32::calcNormalTetra(pf, (float)eps);
                            e = glm::dvec3(r);
                        }
                        double c = glm::dot(e, n);
                        if (!std::isfinite(c)) { ++bad; continue; }
                        err.push_back(std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI);
                    }
                    NormalStats s;
                    s.precision = dbl ? "double" : "float";
                    s.shape = shapes[shape];
                    s.method = methods[m];
                    s.eps = eps;
                    s.p50 = Pct(err, 0.5);
                    s.p99 = Pct(err, 0.99);
                    s.max = err.empty() ? 0 : *std::max_element(err.begin(), err.end());
                    s.nonFinite = (int)bad;
                    out.push_back(s);
                }
    return out;
}

std::string NormalStatsMarkdown(const std::vector<NormalStats>& stats) {
    std::ostringstream m;
    m << "| precision | shape | offset | central p50 / p99 / max deg | forward p50 / p99 / max deg | tetrahedron p50 / p99 / max deg |\n"
         "|---|---|---:|---|---|---|\n";
    for (size_t i = 0; i + 2 < stats.size(); i += 3) {
        char b[512];
        std::snprintf(b, sizeof b, "| %s | %s | %g |", stats[i].precision.c_str(), stats[i].shape.c_str(), stats[i].eps);
        m << b;
        for (int k = 0; k < 3; ++k) {
            const NormalStats& s = stats[i + k];
            std::snprintf(b, sizeof b, " %.3g / %.3g / %.3g |", s.p50, s.p99, s.max);
            m << b;
        }
        m << "\n";
    }
    return m.str();
}

}  // namespace sdfvj::accuracy
