// The eight shipped post effects (shaders/isf/), each on a known input, asserting what it is for.
// Tolerances are in 8-bit levels and stated per check.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>

#include "isf_test_util.h"

using namespace sdfvj;
using namespace sdfvj::isftest;

namespace {

using Px = std::array<uint8_t, 4>;

// A texture-sized pattern with detail everywhere (no symmetry of its own).
Px Pattern(int x, int y) { return {uint8_t((x * 37 + y * 11) % 251), uint8_t((x * 5 + y * 23) % 241), uint8_t((x * y * 3) % 239), 255}; }

Img Run(const std::string& effect, int w, int h, const std::function<Px(int, int)>& input,
        const std::vector<std::pair<std::string, float>>& params = {}, int frame = 0) {
    IsfEffect e;
    LoadOrFail(e, ShippedEffect(effect));
    const unsigned tex = MakeTexture(w, h, input);
    IsfFrameInputs in;
    in.params = params;
    in.frame = frame;
    const Img out = ReadBack(e.Render(tex, w, h, in), w, h);
    DeleteTexture(tex);
    return out;
}

int MaxDiff(const Img& a, const Img& b) {
    int worst = 0;
    for (size_t i = 0; i < a.px.size(); ++i) worst = std::max(worst, std::abs(a.px[i] - b.px[i]));
    return worst;
}

Img ToImg(int w, int h, const std::function<Px(int, int)>& f) {
    Img img{w, h, std::vector<uint8_t>((size_t)w * h * 4)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 4; ++c) img.px[((size_t)y * w + x) * 4 + c] = f(x, y)[c];
    return img;
}

}  // namespace

TEST_CASE("isf effect mirror: one half is the other half flipped (within 1/255)", "[isf][effects]") {
    RequireGl();
    const int w = 64, h = 48;
    const Img out = Run("mirror", w, h, Pattern);
    Save("effect_mirror", out);
    int worst = 0, keep = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w / 2; ++x)
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, std::abs(out.At(x, y, c) - out.At(w - 1 - x, y, c)));
                keep = std::max(keep, std::abs(out.At(x, y, c) - Pattern(x, y)[c]));
            }
    CHECK(worst <= 1);
    CHECK(keep <= 1);   // the left half is the input
    const Img vertical = Run("mirror", w, h, Pattern, {{"mode", 2}});   // bottom onto top
    worst = 0;
    for (int y = 0; y < h / 2; ++y)
        for (int x = 0; x < w; ++x) worst = std::max(worst, std::abs(vertical.At(x, y, 0) - vertical.At(x, h - 1 - y, 0)));
    CHECK(worst <= 1);
    CHECK(vertical.At(5, 40, 0) == Pattern(5, 40)[0]);   // the bottom half is kept
}

TEST_CASE("isf effect rgb_split: red and blue are shifted by amount pixels, green stays", "[isf][effects]") {
    RequireGl();
    const Img out = Run("rgb_split", 48, 16, [](int x, int) { return x == 20 ? Px{255, 255, 255, 255} : Px{0, 0, 0, 255}; },
                        {{"amount", 4}});
    Save("effect_rgb_split", out);
    for (int x = 0; x < 48; ++x) {
        INFO("x = " << x);
        CHECK(out.At(x, 8, 0) == (x == 16 ? 255 : 0));   // red reads 4 to the right: the line shows 4 to the left
        CHECK(out.At(x, 8, 1) == (x == 20 ? 255 : 0));
        CHECK(out.At(x, 8, 2) == (x == 24 ? 255 : 0));
    }
    CHECK(MaxDiff(Run("rgb_split", 48, 16, Pattern, {{"amount", 0}}), ToImg(48, 16, Pattern)) <= 1);   // 0 = no change
}

TEST_CASE("isf effect color_grade: defaults are the identity, saturation 0 is grey, +1 stop doubles", "[isf][effects]") {
    RequireGl();
    CHECK(MaxDiff(Run("color_grade", 32, 32, Pattern), ToImg(32, 32, Pattern)) <= 1);
    const Img grey = Run("color_grade", 32, 32, Pattern, {{"saturation", 0}});
    Save("effect_color_grade_grey", grey);
    int spread = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            spread = std::max({spread, std::abs(grey.At(x, y, 0) - grey.At(x, y, 1)), std::abs(grey.At(x, y, 1) - grey.At(x, y, 2))});
    CHECK(spread <= 1);
    const Img bright = Run("color_grade", 8, 8, [](int, int) { return Px{60, 30, 100, 255}; }, {{"exposure", 1}});
    CHECK((bright.At(4, 4, 0) == 120 && bright.At(4, 4, 1) == 60 && bright.At(4, 4, 2) == 200));
    const Img tinted = Run("color_grade", 8, 8, [](int, int) { return Px{200, 200, 200, 255}; }, {{"gain_b", 0.5}});
    CHECK((tinted.At(4, 4, 0) == 200 && tinted.At(4, 4, 2) == 100));
}

TEST_CASE("isf effect film_grain: zero-mean noise of the stated strength, new each frame, same for the same frame", "[isf][effects]") {
    RequireGl();
    auto grey = [](int, int) { return Px{128, 128, 128, 255}; };
    const Img a = Run("film_grain", 64, 64, grey, {}, 0), a2 = Run("film_grain", 64, 64, grey, {}, 0);
    const Img b = Run("film_grain", 64, 64, grey, {}, 1);
    Save("effect_film_grain", a);
    double sum = 0, sq = 0;
    int changed = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const double d = a.At(x, y, 1) - 128.0;
            sum += d;
            sq += d * d;
            changed += a.At(x, y, 1) != b.At(x, y, 1);
        }
    const double mean = sum / 4096, sd = std::sqrt(sq / 4096 - mean * mean);
    CHECK(std::fabs(mean) < 1.5);                // zero mean: the picture keeps its brightness
    CHECK(sd == Approx(0.08 * 255 / std::sqrt(3.0)).epsilon(0.15));   // uniform noise * amount at mid grey
    CHECK(changed > 4096 * 0.8);                 // a new grain every frame
    CHECK(MaxDiff(a, a2) == 0);                  // deterministic: replays render the same bytes
    CHECK(MaxDiff(Run("film_grain", 16, 16, [](int, int) { return Px{0, 0, 0, 255}; }), ToImg(16, 16, [](int, int) { return Px{0, 0, 0, 255}; })) == 0);
}

TEST_CASE("isf effect edge_glow: flat areas keep their colour, an edge glows in the glow colour", "[isf][effects]") {
    RequireGl();
    const Img out = Run("edge_glow", 32, 16, [](int x, int) { return x < 16 ? Px{0, 0, 0, 255} : Px{255, 255, 255, 255}; });
    Save("effect_edge_glow", out);
    for (int x : {2, 8, 13}) CHECK((out.At(x, 8, 0) == 0 && out.At(x, 8, 1) == 0 && out.At(x, 8, 2) == 0));
    for (int x : {18, 24, 30}) CHECK((out.At(x, 8, 0) == 255 && out.At(x, 8, 1) == 255));
    // the black pixel next to the edge: Sobel |g| = 4 -> edge 1 -> glow colour (0.2, 0.8, 1.0)
    CHECK(std::abs(out.At(15, 8, 0) - 51) <= 1);
    CHECK(std::abs(out.At(15, 8, 1) - 204) <= 1);
    CHECK(out.At(15, 8, 2) == 255);
}

TEST_CASE("isf effect kaleidoscope: N-fold rotational and mirror symmetry about the centre", "[isf][effects]") {
    RequireGl();
    const int n = 64;
    auto smooth = [](int x, int y) { return Px{uint8_t(x * 4), uint8_t(y * 4), uint8_t(255 - (x + y) * 2), 255}; };
    const Img out = Run("kaleidoscope", n, n, smooth, {{"sides", 4}});
    Save("effect_kaleidoscope", out);
    int rotated = 0, mirrored = 0, fromInput = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            // 90 degrees about the centre maps pixel (x, y) to (n-1-y, x); the wedge edge y = centre mirrors
            rotated += std::abs(out.At(x, y, 0) - out.At(n - 1 - y, x, 0)) > 2;
            mirrored += std::abs(out.At(x, y, 1) - out.At(x, n - 1 - y, 1)) > 2;
            fromInput += std::abs(out.At(x, y, 0) - smooth(x, y)[0]) > 8;
        }
    CHECK(rotated < n * n / 100);   // seams where atan wraps may differ in a few pixels
    CHECK(mirrored < n * n / 100);
    CHECK(fromInput > n * n / 4);   // it did fold the picture
}

TEST_CASE("isf effect feedback_trails: a pixel that goes dark fades as decay^frames", "[isf][effects]") {
    RequireGl();
    IsfEffect e;
    LoadOrFail(e, ShippedEffect("feedback_trails"));
    const unsigned lit = MakeTexture(32, 32, [](int x, int y) { return x >= 4 && x < 12 && y >= 4 && y < 12 ? Px{255, 255, 255, 255} : Px{0, 0, 0, 255}; });
    const unsigned dark = MakeTexture(32, 32, [](int, int) { return Px{0, 0, 0, 255}; });
    IsfFrameInputs in;
    CHECK(ReadBack(e.Render(lit, 32, 32, in), 32, 32).At(8, 8, 0) == 255);
    in.frame = 1;
    Img one = ReadBack(e.Render(dark, 32, 32, in), 32, 32);
    in.frame = 2;
    Img two = ReadBack(e.Render(dark, 32, 32, in), 32, 32);
    Save("effect_feedback_trails", two);
    DeleteTexture(lit);
    DeleteTexture(dark);
    CHECK(std::abs(one.At(8, 8, 0) - 230) <= 1);   // 0.9 * 255
    CHECK(std::abs(two.At(8, 8, 0) - 207) <= 1);   // 0.81 * 255
    CHECK(two.At(20, 20, 0) == 0);                 // never lit: stays black
}

TEST_CASE("isf effect bloom: highlights glow into their surroundings, an image without highlights is unchanged", "[isf][effects]") {
    RequireGl();
    auto dim = [](int x, int y) { return Px{uint8_t(x * 2), uint8_t(100), uint8_t(y * 2), 255}; };   // luma < 0.85 (the threshold) everywhere
    CHECK(MaxDiff(Run("bloom", 64, 64, dim), ToImg(64, 64, dim)) <= 1);
    auto spot = [](int x, int y) { return x >= 28 && x < 36 && y >= 28 && y < 36 ? Px{255, 255, 255, 255} : Px{0, 0, 0, 255}; };
    const Img out = Run("bloom", 64, 64, spot);
    Save("effect_bloom", out);
    CHECK(out.At(32, 32, 0) == 255);   // the highlight itself
    CHECK(out.At(38, 32, 0) > 20);     // 2-3 pixels outside it: glow
    CHECK(out.At(32, 25, 1) > 20);
    CHECK(out.At(38, 32, 0) > out.At(44, 32, 0));   // falling off with distance
    CHECK(out.At(2, 2, 0) == 0);       // far away: still black
}
