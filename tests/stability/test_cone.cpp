// The compute path's cone pre-pass (render.glsl coneStart, main_comp.glsl): one cone per 8x8 tile
// tells every primary ray of the tile where it may start. It is a shortcut, not an approximation:
// no pixel ray's surface may lie before its tile's start (CPU, double, against a converged march),
// the image stays what the march from the eye draws, and it must save steps where it is meant to.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gl_fixture.h"
#include "stability_util.h"

using namespace sdfvj;
using namespace stability;

namespace {

constexpr int kTile = 8;   // main_comp.glsl's CONE_TILE

// The cone of tile (tx, ty) of a w x h frame: as the frame runs it, or `unfolded` (CONE_MIRROR's).
template <typename S>
S TileStart(accuracy::CpuScene<S>& s, int tx, int ty, int w, int h, bool unfolded = false) {
    using V2 = typename accuracy::CpuScene<S>::V2;
    V2 lo(S(tx * kTile) + S(0.5), S(ty * kTile) + S(0.5));
    V2 hi(std::min(lo.x + S(kTile - 1), S(w) - S(0.5)), std::min(lo.y + S(kTile - 1), S(h) - S(0.5)));
    return unfolded ? s.coneStartUnfolded(lo, hi) : s.coneStart(lo, hi);
}

// 640x360: an 8x8 tile spans the angle it does in a real frame (at a few dozen pixels a tile would
// be a quarter of the picture and its cone would stop at once). In each probed tile its corners,
// centre and four more pixels, where a bundle's edge rays graze first.
constexpr int kW = 640, kH = 360;
constexpr int kProbe[9][2] = {{0, 0}, {7, 0}, {0, 7}, {7, 7}, {4, 4}, {2, 5}, {6, 1}, {1, 3}, {5, 6}};

// The surface itself: a march of the double build converged far past the renderer's threshold.
accuracy::CpuRay<double> Converged(accuracy::CpuScene<double>& s, glm::dvec3 ro, glm::dvec3 rd) {
    const int steps = *s.maxSteps;
    const double eps = *s.hitEps;
    *s.maxSteps = 20000;
    *s.hitEps = 1e-7;
    auto r = s.march(ro, rd, 0.0);
    *s.maxSteps = steps;
    *s.hitEps = eps;
    return r;
}

// At most the first `corners` corners of the parameter box and `random` random points.
std::vector<Params> SomePoints(const SceneInfo& scene, size_t corners, int random) {
    auto all = ParamPoints(scene, 0);
    if (all.size() > corners) all.resize(corners);
    auto rnd = ParamPoints(scene, random, 19);
    rnd.erase(rnd.begin(), rnd.begin() + (ptrdiff_t)(rnd.size() - (size_t)random));
    all.insert(all.end(), rnd.begin(), rnd.end());
    return all;
}

}  // namespace

TEST_CASE("stability: no pixel's surface lies before its tile's cone start, and the cone saves primary steps", "[stability][cpu][cone]") {
    // Every 9th tile of a kW x kH frame, kProbe's pixels in each.
    const int w = kW, h = kH;
    const int tilesX = w / kTile, tilesY = h / kTile;
    int scenes = 0;
    for (const std::string& name : accuracy::CpuSceneNames()) {
        SceneInfo scene;
        std::string error;
        REQUIRE(FindScene(name, &scene, &error));
        auto s = accuracy::MakeCpuScene64(name);
        ++scenes;
        long pixels = 0, before = 0, hits = 0, floorPast = 0, floorPastStart = 0;
        double stepsFromEye = 0, stepsFromCone = 0, worst = -1e30;
        std::string first;
        auto points = SomePoints(scene, 4, 2);
        for (size_t i = 0; i < points.size(); ++i) {
            FrameInputs in;
            in.params = points[i];
            in.time = 0.37 * i;
            in.beat = 0.25f;
            accuracy::ApplyFrame(s, scene, in, w, h);   // the shipped quality: the cone as it runs
            for (int k = (int)i; k < tilesX * tilesY; k += 9) {
                const int tx = k % tilesX, ty = k / tilesX;
                const double start = TileStart(s, tx, ty, w, h);
                for (const auto& o : kProbe) {
                    const int x = tx * kTile + o[0], y = ty * kTile + o[1];
                    ++pixels;
                    const glm::dvec3 ro = *s.camPos, rd = s.cameraRay(glm::dvec2(x + 0.5, y + 0.5));
                    stepsFromEye += s.march(ro, rd, 0.0).steps;
                    stepsFromCone += s.march(ro, rd, start).steps;
                    auto exact = Converged(s, ro, rd);
                    if (!exact.hit || exact.steps >= 20000) continue;
                    // A scene of objects over a floor (CONE_PAST_FLOOR): its cone goes past the floor's
                    // plane, which the march meets analytically; the objects stay behind the start.
                    const glm::dvec3 p = ro + rd * exact.t;
                    if (s.hasUnfoldedCone && rd.y < 0.0 && std::abs(p.y) <= 1e-6 * std::max(1.0, exact.t)) {
                        ++floorPast;
                        floorPastStart += start > exact.t;
                        continue;
                    }
                    ++hits;
                    const double over = (start - exact.t) / std::max(1.0, exact.t);
                    worst = std::max(worst, over);
                    if (over > 1e-9) {
                        ++before;
                        if (first.empty()) {
                            char m[200];
                            std::snprintf(m, sizeof m, "knob point %zu pixel %d,%d: surface at t=%.6f, tile starts at %.6f", i, x, y,
                                          exact.t, start);
                            first = m;
                        }
                    }
                }
            }
        }
        const double eyeMean = stepsFromEye / double(pixels), coneMean = stepsFromCone / double(pixels);
        INFO(name << ": " << pixels << " pixels, " << hits << " hits; primary steps a pixel " << eyeMean << " from the eye, "
                  << coneMean << " from the cone; nearest start to a surface (relative, < 0 is before it) " << worst
                  << (first.empty() ? "" : "; first: " + first));
        WARN(name << ": primary steps a pixel " << eyeMean << " from the eye, " << coneMean << " from the cone");
        INFO(floorPast << " probed pixels on the floor, " << floorPastStart << " of them start past it");
        CHECK(hits > 0);
        CHECK(before == 0);   // never past a surface
        if (s.hasUnfoldedCone) CHECK(floorPastStart > 0);   // the cone does go past the floor
        if (s.lipschitz() > 1.0) CHECK(coneMean == eyeMean);   // an estimate (the Mandelbulb's): no cone, from the eye
        else CHECK(coneMean < eyeMean);
        if (name == "character" || name == "field150") CHECK(coneMean <= 0.85 * eyeMean);
    }
    CHECK(scenes >= 4);
}

TEST_CASE("stability: the unfolded cone starts a ray reflected off the floor before its surface and saves its steps", "[stability][cpu][cone]") {
    // CONE_MIRROR (march.glsl): with reflections on, a tile's cone goes on through the floor as the
    // mirror image of its rays, and a ray reflected off the floor starts at the cone's distance
    // less the primary ray's length. CPU, double: for the probed pixels whose surface is the floor,
    // the reflected ray's own surface (a converged march) never lies before that start; for the
    // others the cone stays before the primary surface; and the reflected march saves steps.
    const int w = kW, h = kH;
    const int tilesX = w / kTile, tilesY = h / kTile;
    int scenes = 0;
    for (const std::string& name : accuracy::CpuSceneNames()) {
        auto s = accuracy::MakeCpuScene64(name);
        if (!s.hasUnfoldedCone) continue;
        ++scenes;
        SceneInfo scene;
        std::string error;
        REQUIRE(FindScene(name, &scene, &error));
        long floorPixels = 0, reflectedHits = 0, before = 0, primaryBefore = 0;
        double stepsFromFloor = 0, stepsFromCone = 0;
        std::string first;
        auto points = SomePoints(scene, 2, 2);
        for (size_t i = 0; i < points.size(); ++i) {
            FrameInputs in;
            in.params = points[i];
            in.time = 0.37 * i;
            in.beat = 0.25f;
            accuracy::ApplyFrame(s, scene, in, w, h);
            for (int k = (int)i; k < tilesX * tilesY; k += 9) {
                const int tx = k % tilesX, ty = k / tilesX;
                const double start = TileStart(s, tx, ty, w, h, true);
                for (const auto& o : kProbe) {
                    const glm::dvec3 ro = *s.camPos, rd = s.cameraRay(glm::dvec2(tx * kTile + o[0] + 0.5, ty * kTile + o[1] + 0.5));
                    auto exact = Converged(s, ro, rd);
                    if (!exact.hit || exact.steps >= 20000) continue;
                    const glm::dvec3 p = ro + rd * exact.t;
                    const bool onFloor = rd.y < 0.0 && std::abs(p.y) <= 1e-6 * std::max(1.0, exact.t);
                    if (!onFloor) {   // the primary ray's start, as the cone's
                        primaryBefore += (start - exact.t) / std::max(1.0, exact.t) > 1e-9;
                        continue;
                    }
                    const glm::dvec3 up(rd.x, -rd.y, rd.z);   // the reflected ray (the floor's normal is straight up)
                    if (up.y < s.hitEpsilon(1.0)) continue;    // too flat: mirrorStart gives it no start
                    ++floorPixels;
                    const double mirror = std::max(start - exact.t, 0.0);
                    // what traceRay marches: from 4 hit thresholds above the plane
                    const glm::dvec3 from(p.x, 4.0 * s.hitEpsilon(exact.t), p.z);
                    stepsFromFloor += s.march(from, up, 0.0).steps;
                    stepsFromCone += s.march(from, up, mirror).steps;
                    auto reflected = Converged(s, glm::dvec3(p.x, 1e-6, p.z), up);
                    if (!reflected.hit || reflected.steps >= 20000) continue;
                    ++reflectedHits;
                    if ((mirror - reflected.t) / std::max(1.0, reflected.t) > 1e-9) {
                        ++before;
                        if (first.empty())
                            first = "knob point " + std::to_string(i) + " tile " + std::to_string(tx) + "," + std::to_string(ty) +
                                    ": reflected surface at s=" + std::to_string(reflected.t) + ", start " + std::to_string(mirror);
                    }
                }
            }
        }
        INFO(name << ": " << floorPixels << " probed pixels on the floor, " << reflectedHits << " of their reflections meet a surface, "
                  << before << " of them before the start" << (first.empty() ? "" : " (" + first + ")") << "; " << primaryBefore
                  << " primary surfaces before the start; reflected steps a floor pixel " << stepsFromFloor / std::max(1L, floorPixels)
                  << " from the floor, " << stepsFromCone / std::max(1L, floorPixels) << " from the cone");
        WARN(name << ": reflected steps a floor pixel " << stepsFromFloor / std::max(1L, floorPixels) << " from the floor, "
                  << stepsFromCone / std::max(1L, floorPixels) << " from the unfolded cone");
        CHECK(floorPixels > 0);
        CHECK(reflectedHits > 0);
        CHECK(before == 0);
        CHECK(primaryBefore == 0);
        CHECK(stepsFromCone < stepsFromFloor);
    }
    CHECK(scenes >= 3);   // character, field50, field150
}

TEST_CASE("stability: the cone pre-pass draws what the march from the eye draws (CPU float, 2/255 on 99 % of pixels)", "[stability][cpu][cone]") {
    // CPU float frames (the GPU's arithmetic) with and without the cone, and the double build's
    // frame from the eye: the two float frames agree within 2/255 on 99 % of pixels, and the
    // cone's is no further from the double frame than the eye's. (The Mandelbulb, whose field is
    // an estimate, marches from the eye: its frames are the same.)
    const int w = 192, h = 108;
    for (const std::string& name : accuracy::CpuSceneNames()) {
        SceneInfo scene;
        std::string error;
        REQUIRE(FindScene(name, &scene, &error));
        auto s = accuracy::MakeCpuScene32(name);
        auto ref = accuracy::MakeCpuScene64(name);
        FrameInputs in;
        in.time = 1.0;
        accuracy::ApplyFrame(s, scene, in, w, h);
        accuracy::ApplyFrame(ref, scene, in, w, h);
        long pixels = 0, off2 = 0, off8 = 0, eyeOffRef = 0, coneOffRef = 0;
        float worst = 0;
        auto diff = [](auto a, auto b) {
            return (float)std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
        };
        for (int ty = 0; ty * kTile < h; ++ty)
            for (int tx = 0; tx * kTile < w; ++tx) {
                const float start = TileStart(s, tx, ty, w, h);
                for (int y = ty * kTile; y < std::min(h, (ty + 1) * kTile); ++y)
                    for (int x = tx * kTile; x < std::min(w, (tx + 1) * kTile); ++x) {
                        const glm::vec2 c(x + 0.5f, y + 0.5f);
                        const glm::vec4 a = s.render(c), b = s.renderFrom(c, start);
                        const glm::dvec4 r = ref.render(glm::dvec2(x + 0.5, y + 0.5));
                        const float d = diff(a, b);
                        worst = std::max(worst, d);
                        ++pixels;
                        off2 += d > 2.0f / 255.0f;
                        off8 += d > 8.0f / 255.0f;
                        eyeOffRef += diff(glm::dvec4(a), r) > 8.0f / 255.0f;
                        coneOffRef += diff(glm::dvec4(b), r) > 8.0f / 255.0f;
                    }
            }
        INFO(name << ": " << off2 << " of " << pixels << " pixels off by more than 2/255, " << off8 << " by more than 8/255, worst "
                  << worst * 255.0f << "/255; off the double reference by more than 8/255: " << eyeOffRef << " from the eye, "
                  << coneOffRef << " with the cone");
        CHECK(coneOffRef <= eyeOffRef + pixels / 200);
        CHECK(off2 <= pixels / 100);
        CHECK(off8 <= pixels / 200);
        if (name == "mandelbulb") CHECK(off2 == 0);
    }
}

TEST_CASE("stability: on the GPU compute path the cone pre-pass finds the same surfaces in fewer steps", "[stability][gpu][cone]") {
    test::RequireGl();
    for (const char* name : {"character", "field150", "midi"}) {
        SceneInfo scene;
        std::string error;
        REQUIRE(FindScene(name, &scene, &error));
        FloatRender geo;
        REQUIRE(geo.Build(scene, scene.effects, RenderPath::Compute, 4, 640, 360, &error));
        FrameInputs in;
        in.time = 1.0;
        in.quality.conePrepass = false;
        const std::vector<float> eye = geo.Draw(scene, in);
        in.quality.conePrepass = true;
        const std::vector<float> cone = geo.Draw(scene, in);
        REQUIRE(eye.size() == cone.size());
        long pixels = 0, hitsAgree = 0, hitsEye = 0, tOff = 0;
        double stepsEye = 0, stepsCone = 0;
        for (size_t i = 0; i + 3 < eye.size(); i += 4) {
            ++pixels;
            stepsEye += std::floor(eye[i + 3]);
            stepsCone += std::floor(cone[i + 3]);
            if (eye[i] < 0) continue;
            ++hitsEye;
            if (cone[i] < 0) continue;
            ++hitsAgree;
            if (std::abs(eye[i] - cone[i]) > 0.01f * std::max(1.0f, eye[i])) ++tOff;
        }
        INFO(name << ": " << hitsEye << " hits from the eye, " << hitsAgree << " with the cone too, " << tOff
                  << " of them 1 % apart; steps a pixel " << stepsEye / pixels << " from the eye, " << stepsCone / pixels << " from the cone");
        CHECK(hitsEye > pixels / 10);
        CHECK(hitsAgree >= hitsEye - hitsEye / 100);
        CHECK(tOff <= hitsEye / 100);
        CHECK(stepsCone < 0.85 * stepsEye);

        // The quick tier of a tiered compile leaves the cone out (one map() call site less to
        // compile): its pre-pass writes 0 and every ray marches from the eye, as with the cone off.
        EffectSet e = scene.effects;
        e.debugView = 4;
        ShaderSource src;
        REQUIRE(AssembleProgram(scene, VariantKey{scene.path, e, RenderPath::Compute}, &src, &error));
        PendingProgram pending;
        pending.Begin(src, RenderPath::Compute, BuildTier::Quick);
        Program quick;
        std::string log;
        REQUIRE(pending.Finish(&quick, &log));
        in.quality.conePrepass = true;
        geo.fr.Draw(quick, scene, in);
        const std::vector<float> quickFrame = geo.fr.ReadPixelsFloat();
        double stepsQuick = 0;
        for (size_t i = 3; i < quickFrame.size(); i += 4) stepsQuick += std::floor(quickFrame[i]);
        CHECK(stepsQuick == stepsEye);
    }
}
