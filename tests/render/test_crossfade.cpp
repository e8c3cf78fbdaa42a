// Crossfade: a scene change that morphs mixes the old scene's frame with the new one's.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>

#include "app/show.h"
#include "gl_fixture.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

// Renders `scene` into `fr` with its own effects on the fragment path.
void RenderInto(FrameRenderer& fr, const std::string& scene) {
    ShowOptions so;
    so.scene = scene;
    so.path = "fragment";
    Show show;
    std::string err;
    REQUIRE(PrepareShow(so, &show, &err));
    INFO(err);
    REQUIRE(BuildShow(&show, "fragment", &err, false));
    FrameInputs in;
    in.time = 1.0;
    in.params = show.params;
    fr.Draw(*show.program, show.scene, in);
}

}  // namespace

TEST_CASE("crossfade: the mix of two scenes' frames is each at its end and their average half way", "[crossfade]") {
    RequireGl();
    const int w = 64, h = 36;
    FrameRenderer a, b, out;
    std::string err;
    REQUIRE(a.Resize(w, h, &err));
    REQUIRE(b.Resize(w, h, &err));
    REQUIRE(out.Resize(w, h, &err));
    RenderInto(a, "midi");
    RenderInto(b, "primitives");
    const Image ia{w, h, a.ReadPixels()}, ib{w, h, b.ReadPixels()};
    REQUIRE(CompareImages(ia, ib, 8).fractionOver > 0.05);   // two different pictures

    Crossfade fade;
    INFO(err);
    REQUIRE(fade.Init(&err));
    fade.Draw(a.Texture(), b.Texture(), 0.0f, out.Framebuffer(), w, h);
    CHECK(CompareImages(ia, Image{w, h, out.ReadPixels()}, 0).maxAbs <= 1);
    fade.Draw(a.Texture(), b.Texture(), 1.0f, out.Framebuffer(), w, h);
    CHECK(CompareImages(ib, Image{w, h, out.ReadPixels()}, 0).maxAbs <= 1);
    fade.Draw(a.Texture(), b.Texture(), 0.5f, out.Framebuffer(), w, h);
    const Image half{w, h, out.ReadPixels()};
    int worst = 0;
    for (size_t i = 0; i < half.rgba.size(); ++i) {
        const int avg = (ia.rgba[i] + ib.rgba[i] + 1) / 2;
        worst = std::max(worst, std::abs(half.rgba[i] - avg));
    }
    CHECK(worst <= 1);   // 8-bit rounding is the only difference
}

TEST_CASE("orbit: the mouse orbit turns the camera around its target at the same distance", "[crossfade]") {
    SceneInfo s;
    s.camPos = {0, 2, -6};
    s.camTarget = {0, 1, 0};
    auto dist = [&](const Vec3f& p) {
        return std::sqrt((p[0] - 0) * (p[0] - 0) + (p[1] - 1) * (p[1] - 1) + (p[2] - 0) * (p[2] - 0));
    };
    CHECK(OrbitCamera(s, 0, 0) == s.camPos);
    const Vec3f half = OrbitCamera(s, 3.14159265f, 0);      // half a turn: behind the target
    CHECK(half[0] == Approx(0).margin(1e-4));
    CHECK(half[1] == Approx(2));
    CHECK(half[2] == Approx(6));
    const Vec3f quarter = OrbitCamera(s, 1.5707963f, 0.3f);
    CHECK(dist(quarter) == Approx(dist(s.camPos)));
    CHECK(quarter[1] > 2.0f);                               // pitched up
    const Vec3f pole = OrbitCamera(s, 0, 10.0f);            // held short of the pole
    CHECK(pole[1] - 1 < dist(s.camPos));
    CHECK(std::fabs(pole[2]) > 0.01f);
}
