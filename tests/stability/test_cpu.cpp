// CPU side of the stability suite: the scenes and render.glsl compiled as C++ in float and
// double. What tests/sdf already covers is not repeated here: operator guards at k = 0 / huge k,
// exponential smin far away, scale near 0, ellipsoid centre, Mandelbulb r = 0 at power 8
// (lib_cases.inc, operator_cases.inc), per-operator Lipschitz bounds (operator_cases.inc) and
// the scenes' bounds at every knob extreme (test_sdf_scenes.cpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <random>

#include "sdf/sdf32.h"
#include "sdf/sdf64.h"
#include "stability_util.h"

using namespace sdfvj;
using namespace stability;

namespace {

template <class S>
int NonFiniteFrame(accuracy::CpuScene<S>& s, int w, int h) {
    int bad = 0;
    using V2 = typename accuracy::CpuScene<S>::V2;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            V2 c(S(x + 0.5), S(y + 0.5));
            auto col = s.render(c);
            auto rd = s.cameraRay(c);
            auto r = s.march(*s.camPos, rd, S(0));
            auto n = s.surfaceNormal(*s.camPos + rd * r.t, r.t);
            if (!std::isfinite(double(col.x + col.y + col.z + col.w)) || !std::isfinite(double(r.t)) ||
                !std::isfinite(double(n.x + n.y + n.z)))
                ++bad;
        }
    return bad;
}

}  // namespace

TEST_CASE("stability: every scene over its whole parameter range is finite in the CPU float and double builds", "[stability][cpu]") {
    const int w = 12, h = 9;
    for (const std::string& name : accuracy::CpuSceneNames()) {
        SceneInfo scene;
        std::string error;
        REQUIRE(FindScene(name, &scene, &error));
        auto s32 = accuracy::MakeCpuScene32(name);
        auto s64 = accuracy::MakeCpuScene64(name);
        auto points = ParamPoints(scene, 4);
        int bad = 0;
        std::string firstBad;
        for (size_t i = 0; i < points.size(); ++i) {
            FrameInputs in;
            in.params = points[i];
            in.time = 0.37 * i;
            accuracy::ApplyFrame(s32, scene, in, w, h);
            accuracy::ApplyFrame(s64, scene, in, w, h);
            int b = NonFiniteFrame(s32, w, h) + NonFiniteFrame(s64, w, h);
            if (b && !bad) firstBad = Describe(points[i]);
            bad += b;
        }
        INFO(name << ": first bad point " << firstBad);
        CHECK(bad == 0);
        std::printf("stability cpu: %s: %zu parameter points, float and double, %dx%d: %d non-finite pixels\n",
                    name.c_str(), points.size(), w, h, bad);
    }
}

TEST_CASE("stability: hard geometry in the CPU builds matches analytic intersections", "[stability][cpu]") {
    SceneInfo scene;
    std::string error;
    REQUIRE(LoadScene(TestScene("stability_hard.glsl"), &scene, &error));
    auto s32 = Hard32();
    auto s64 = Hard64();
    struct Case { const char* what; float shape, offset, radius, eps, maxDist; Vec3f cam, target; int steps; };
    for (Case c : {Case{"sphere", 1, 0, 1, 1e-3f, 50, {0, 1, -5}, {0, 1, 0}, 128},
                   Case{"box", 2, 0, 1, 1e-3f, 50, {1.5f, 2.5f, -4}, {0, 1, 0}, 128},
                   Case{"sphere 10^4 away", 1, 1e4f, 2000, 1e-3f, 2e4f, {0, 1, -5}, {0, 1, 1e4f}, 256},
                   Case{"eps below float resolution at 10^4", 1, 1e4f, 2000, 1e-12f, 2e4f, {0, 1, -5}, {0, 1, 1e4f}, 256},
                   Case{"ellipsoid", 8, 0, 1, 1e-3f, 50, {1.5f, 2.0f, -4}, {0, 1, 0}, 128},
                   Case{"torus", 3, 0, 1, 1e-3f, 50, {1.5f, 2.5f, -4}, {0, 1, 0}, 128},
                   Case{"grazing floor", 0, 0, 1, 1e-3f, 50, {0, 0.01f, -5}, {0, 0.01f, 0}, 128}}) {
        scene.camPos = c.cam;
        scene.camTarget = c.target;
        FrameInputs in;
        in.params = {{"shape", c.shape}, {"k", 0.5f}, {"offset", c.offset}, {"radius", c.radius}};
        in.quality.hitEps = c.eps;
        in.quality.maxDist = c.maxDist;
        in.quality.maxSteps = c.steps;
        const int w = 24, h = 16;
        accuracy::ApplyFrame(s32, scene, in, w, h);
        accuracy::ApplyFrame(s64, scene, in, w, h);
        double angle = accuracy::PixelAngle(scene, h);
        double worst32 = 0, worst64 = 0;
        int nonFinite = 0, compared = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                glm::dvec3 rd = s64.cameraRay(glm::dvec2(x + 0.5, y + 0.5));
                glm::dvec3 ro = *s64.camPos;
                double t = -1;
                if (c.shape == 1) {
                    glm::dvec3 oc = ro - glm::dvec3(0, 1, c.offset);
                    double b = glm::dot(oc, rd), disc = b * b - (glm::dot(oc, oc) - double(c.radius) * c.radius);
                    if (disc >= 0) t = -b - std::sqrt(disc);
                    double tf = rd.y < 0 ? -ro.y / rd.y : -1;
                    if (tf >= 0 && (t < 0 || tf < t)) t = -1;   // the floor is in front: not compared
                } else if (c.shape == 2) {
                    // slab test against the box of half-extents (1, 0.6, 0.8) centred at (0, 1, 0)
                    glm::dvec3 lo = glm::dvec3(-1.0, 0.4, -0.8), hi = glm::dvec3(1.0, 1.6, 0.8);
                    double t0 = 0, t1 = 1e30;
                    for (int i = 0; i < 3; ++i) {
                        double a = (lo[i] - ro[i]) / rd[i], b = (hi[i] - ro[i]) / rd[i];
                        t0 = std::max(t0, std::min(a, b));
                        t1 = std::min(t1, std::max(a, b));
                    }
                    if (t0 <= t1) t = t0;
                } else if (c.shape == 8) {
                    // ellipsoid with semi-axes (1, 0.5, 0.25) * radius centred at (0, 1, 0): a
                    // quadratic in the frame where it is the unit sphere
                    glm::dvec3 axes = glm::dvec3(1.0, 0.5, 0.25) * double(c.radius);
                    glm::dvec3 o = (ro - glm::dvec3(0, 1, 0)) / axes, d = rd / axes;
                    double A = glm::dot(d, d), B = glm::dot(o, d), C = glm::dot(o, o) - 1.0;
                    double disc = B * B - A * C;
                    if (disc >= 0) t = (-B - std::sqrt(disc)) / A;
                } else if (c.shape == 3) {
                    // torus (ring radius 1, tube 0.3) centred at (0, 1, 0), its axis along Z (the
                    // scene turns fTorus's Y axis by 90 degrees about X): the first root of its
                    // quartic (|u|^2 + R^2 - r^2)^2 - 4 R^2 (u.x^2 + u.y^2) along the ray, bracketed
                    // on a fine grid and bisected
                    auto f = [&](double tt) {
                        glm::dvec3 u = ro + rd * tt - glm::dvec3(0, 1, 0);
                        double q = glm::dot(u, u) + 1.0 - 0.09;
                        return q * q - 4.0 * (u.x * u.x + u.y * u.y);
                    };
                    for (double a = 0, fa = f(0); a < 20 && t < 0; a += 1e-3) {
                        double b = a + 1e-3, fb = f(b);
                        if ((fa > 0) != (fb > 0)) {
                            double lo = a, hi = b;
                            for (int i = 0; i < 60; ++i) {
                                double m = 0.5 * (lo + hi);
                                if ((f(m) > 0) == (fa > 0)) lo = m; else hi = m;
                            }
                            t = 0.5 * (lo + hi);
                        }
                        fa = fb;
                    }
                } else if (rd.y < 0) {
                    t = -ro.y / rd.y;
                }
                auto r64 = s64.march(ro, rd, 0.0);
                auto r32 = s32.march(glm::vec3(ro), glm::vec3(rd), 0.0f);
                auto c32 = s32.render(glm::vec2(x + 0.5f, y + 0.5f));
                if (!std::isfinite(r64.t) || !std::isfinite(r32.t) || !std::isfinite(c32.x + c32.y + c32.z)) ++nonFinite;
                if (t < 0 || t > c.maxDist * 0.5 || !r64.hit || !r32.hit) continue;
                ++compared;
                worst64 = std::max(worst64, std::fabs(r64.t - t) / (t * angle));
                worst32 = std::max(worst32, std::fabs(r32.t - t) / (t * angle));
            }
        std::printf("stability cpu: %-36s t error vs analytic, max over %d pixels: double %.3g, float %.3g pixel footprints\n",
                    c.what, compared, worst64, worst32);
        INFO(c.what << ": double " << worst64 << ", float " << worst32 << " footprints over " << compared);
        CHECK(nonFinite == 0);
        CHECK(compared > 0);
        if (std::string(c.what) != "grazing floor") {
            CHECK(worst64 < 1.0);
            CHECK(worst32 < 1.0);
        }
    }
}

TEST_CASE("stability: Mandelbulb at r = 0, inside the bulb, powers 1..16 is finite", "[stability][cpu]") {
    int bad = 0;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    std::vector<glm::dvec3> pts = {glm::dvec3(0), glm::dvec3(1e-30, 0, 0), glm::dvec3(0, 1e-20, 0), glm::dvec3(0, 0.5, 0),
                                   glm::dvec3(0, -0.5, 0), glm::dvec3(1e-8, 1e-8, 1e-8)};
    for (int i = 0; i < 50; ++i) pts.push_back(glm::dvec3(u(rng), u(rng), u(rng)));
    for (double power = 1.0; power <= 16.0; power += 0.5)
        for (int it : {1, 2, 8, 16})
            for (const auto& p : pts) {
                auto a = sdf32::fMandelbulbTrap(glm::vec3(p), (float)power, it);
                auto b = sdf64::fMandelbulbTrap(p, power, it);
                if (!std::isfinite(a.x + a.y) || !std::isfinite(b.x + b.y)) ++bad;
            }
    CHECK(bad == 0);
    // camera inside the bulb, through render.glsl
    SceneInfo scene;
    std::string error;
    REQUIRE(LoadScene(TestScene("stability_bulb.glsl"), &scene, &error));
    scene.camPos = {0.1f, 0.05f, 0.0f};
    scene.camTarget = {1, 0.3f, 0.5f};
    auto s32 = Bulb32();
    auto s64 = Bulb64();
    int badFrames = 0;
    for (int power : {1, 2, 5, 8, 12, 16}) {
        FrameInputs in;
        in.params = {{"power", (float)power}, {"iterations", 8}};
        accuracy::ApplyFrame(s32, scene, in, 8, 6);
        accuracy::ApplyFrame(s64, scene, in, 8, 6);
        badFrames += NonFiniteFrame(s32, 8, 6) + NonFiniteFrame(s64, 8, 6);
    }
    CHECK(badFrames == 0);
}

namespace {

// Marches the double midi scene along one ray with a step scale of its own choosing.
struct MarchOut { double t; bool hit; };
MarchOut MarchWith(accuracy::CpuScene<double>& s, glm::dvec3 ro, glm::dvec3 rd, double stepScale, double maxDist) {
    double t = 0;
    for (int i = 0; i < 4096; ++i) {
        double d = s.map(ro + rd * t).w;
        if (d < 1e-4 * std::max(1.0, t)) return {t, true};
        t += d * stepScale;
        if (t > maxDist) break;
    }
    return {maxDist, false};
}

// The first point along the ray where the field goes negative, by tiny fixed steps.
double FirstCrossing(accuracy::CpuScene<double>& s, glm::dvec3 ro, glm::dvec3 rd, double maxDist, double dt) {
    for (double t = 0; t < maxDist; t += dt)
        if (s.map(ro + rd * t).w < 0) return t;
    return -1;
}

}  // namespace

TEST_CASE("stability: on the twisted, displaced midi scene the naive step oversteps and the Lipschitz-corrected one does not", "[stability][cpu]") {
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    // The raw field (SCENE_GLOBAL_LIPSCHITZ build): what a plain raymarcher marches. The shipped
    // scene divides the blob by the same bound inside map(), checked at the end.
    REQUIRE(accuracy::HasGlobalLipschitzBuild("midi"));
    auto s = accuracy::MakeCpuSceneGlobal64("midi");
    auto shipped = accuracy::MakeCpuScene64("midi");
    const int w = 48, h = 36;
    const double maxDist = 15, dt = 2e-3;
    for (auto params : {Params{{"twist", 3.0f}, {"displacement", 0.25f}, {"scale", 2.0f}, {"smoothness", 0.0f}},
                        Params{{"twist", -3.0f}, {"displacement", 0.25f}, {"scale", 1.0f}, {"smoothness", 0.35f}}}) {
        FrameInputs in;
        in.time = 1.0;
        in.params = params;
        accuracy::ApplyFrame(s, scene, in, w, h);
        accuracy::ApplyFrame(shipped, scene, in, w, h);
        const double L = std::max(1.0, s.lipschitz());
        REQUIRE(shipped.lipschitz() == Approx(1.0));   // the shipped field is corrected inside map()
        std::atomic<int> naiveOver{0}, correctedOver{0}, shippedOver{0}, rays{0};
        accuracy::ParallelRows(h, 0, [&](int y) {
            for (int x = 0; x < w; ++x) {
                glm::dvec3 ro = *s.camPos, rd = s.cameraRay(glm::dvec2(x + 0.5, y + 0.5));
                double first = FirstCrossing(s, ro, rd, maxDist, dt);
                auto naive = MarchWith(s, ro, rd, 1.0, maxDist);
                auto corrected = MarchWith(s, ro, rd, 1.0 / L, maxDist);
                // overstepped: the march ended past the first surface (went through it) or missed it
                auto over = [&](const MarchOut& m) { return first >= 0 && (!m.hit || m.t > first + 2 * dt + 1e-3 * first); };
                if (over(naive)) ++naiveOver;
                if (over(corrected)) ++correctedOver;
                if (over(MarchWith(shipped, ro, rd, 1.0, maxDist))) ++shippedOver;
                ++rays;
            }
        });
        std::printf("stability cpu: midi %s(Lipschitz bound %.2f): %d rays, naive step (factor 1) oversteps %d, "
                    "corrected (1/%.2f) oversteps %d\n", Describe(params).c_str(), L, rays.load(), naiveOver.load(), L,
                    correctedOver.load());
        INFO(Describe(params) << " L=" << L << ": naive " << naiveOver << ", corrected " << correctedOver);
        CHECK(naiveOver > 0);
        CHECK(correctedOver == 0);
        CHECK(shippedOver == 0);
    }
}

TEST_CASE("stability: sampled gradients stay within the bound the code assumes", "[stability][cpu]") {
    // Operators one by one are covered in tests/sdf (operator_cases.inc: smooth minima, twist,
    // bend, displacement, scale; test_sdf_scenes.cpp: scenes at every knob extreme). Here: the
    // exponential and power smooth minima, and the midi scene at random interior knob values.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    auto grad = [](auto f, glm::dvec3 p) {
        const double e = 1e-6;
        glm::dvec3 g(f(p + glm::dvec3(e, 0, 0)) - f(p - glm::dvec3(e, 0, 0)), f(p + glm::dvec3(0, e, 0)) - f(p - glm::dvec3(0, e, 0)),
                     f(p + glm::dvec3(0, 0, e)) - f(p - glm::dvec3(0, 0, e)));
        return glm::length(g) / (2 * e);
    };
    double worstExp = 0, worstPow = 0;
    for (double k : {0.01, 0.1, 0.5, 2.0})
        for (int i = 0; i < 2000; ++i) {
            glm::dvec3 p(u(rng), u(rng), u(rng));
            auto fe = [&](glm::dvec3 q) { return sdf64::sminExp(sdf64::fSphere(q, 0.7), sdf64::fBox(q - glm::dvec3(0.6, 0, 0), glm::dvec3(0.4)), k); };
            worstExp = std::max(worstExp, grad(fe, p));
            auto fp = [&](glm::dvec3 q) { return sdf64::sminPow(sdf64::fSphere(q, 0.7), sdf64::fBox(q - glm::dvec3(0.6, 0, 0), glm::dvec3(0.4)), 1.0 / k); };
            if (fp(p) > 0) worstPow = std::max(worstPow, grad(fp, p));
        }
    std::printf("stability cpu: |grad| max: exponential smooth min %.4f (bound 1), power smooth min %.4f (no bound claimed)\n",
                worstExp, worstPow);
    CHECK(worstExp <= 1.0 + 1e-4);

    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    auto s = accuracy::MakeCpuScene64("midi");
    double worstRatio = 0;
    for (int i = 0; i < 40; ++i) {
        FrameInputs in;
        in.time = 0.3 * i;
        for (const auto& d : scene.params)
            in.params.emplace_back(d.name, std::uniform_real_distribution<float>(d.minValue, d.maxValue)(rng));
        accuracy::ApplyFrame(s, scene, in, 16, 16);
        double L = std::max(1.0, s.lipschitz());
        for (int j = 0; j < 300; ++j) {
            glm::dvec3 p(u(rng) * 1.5, 1.2 + u(rng), u(rng) * 1.5);
            worstRatio = std::max(worstRatio, grad([&](glm::dvec3 q) { return s.map(q).w; }, p) / L);
        }
    }
    std::printf("stability cpu: midi at 40 random knob positions: max |grad| / sceneLipschitz() = %.4f\n", worstRatio);
    CHECK(worstRatio <= 1.0 + 1e-3);
}

TEST_CASE("stability: tetrahedron, central and forward normals against analytic normals", "[stability][cpu]") {
    auto stats = accuracy::MeasureNormals(1000);
    std::printf("stability cpu: normal angle error against analytic normals (degrees)\n%s",
                accuracy::NormalStatsMarkdown(stats).c_str());
    for (const auto& s : stats) {
        INFO(s.precision << " " << s.shape << " " << s.method << " eps " << s.eps << ": p99 " << s.p99);
        CHECK(s.nonFinite == 0);
        // at the renderer's default offset both second-order methods are well under a degree
        if (s.eps == 1e-3 && s.method != "forward") CHECK(s.p99 < 0.5);
    }
}
