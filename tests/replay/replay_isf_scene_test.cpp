// `render --preset` and `render --replay` with an ISF generator as the scene: a preset whose scene
// is a .fs sets its inputs like a raymarched scene's, a take's OSC moves them through the mapping,
// values past an input's MAX are clamped on every path, and the same take renders the same bytes.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "gl_fixture.h"
#include "proc_util.h"
#include "take/take.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

const std::string kGenerator = SDFVJ_ISF_TEST_FILES "/level_generator.fs";

ControlEvent RawOsc(double t, const std::string& address, float v) {
    ControlEvent e;
    e.time = t;
    e.source = EventSource::Osc;
    e.address = address;
    OscArg a;
    a.type = 'f';
    a.f = v;
    e.args.push_back(a);
    return e;
}

// Red, green, blue of the frame's first pixel.
std::array<int, 3> Pixel(const std::string& dir, int frame) {
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%05d.png", frame);
    Image img;
    INFO(dir + name);
    REQUIRE(LoadPng(dir + name, &img));
    return {img.rgba[0], img.rgba[1], img.rgba[2]};
}

}  // namespace

TEST_CASE("replay isf scene: a preset and a take drive an ISF generator's inputs, clamped to MAX, the same bytes twice") {
    const std::string root = SDFVJ_REPLAY_OUT;
    const std::string dir = FreshDir(root, "isf-scene");
    const std::string preset = dir + "/gen.json", take = dir + "/gen.mid";
    {
        std::ofstream p(preset);
        p << "{\n  \"scene\": \"" << kGenerator << "\",\n  \"params\": {\"level\": 1.5, \"gain\": 2}\n}\n";
    }
    Take t;
    t.events = {RawOsc(0.5, "/sdfvj/raw/level", 0.4f),      // red 0.2
                RawOsc(1.0, "/sdfvj/param/level", 0.75f),   // 0..1 of MIN..MAX: 1.5, red 0.75
                RawOsc(1.5, "/sdfvj/raw/level", 7.0f),      // past MAX 2: clamped, red 1
                RawOsc(1.5, "/sdfvj/raw/gain", -3.0f)};     // below MIN (0, not written): blue 0
    t.duration = 2.0;
    std::string error;
    REQUIRE(WriteTake(take, t, &error));

    auto args = [&](const std::string& out, bool withTake) {
        std::vector<std::string> v = {SDFVJ_BIN, "render", "--preset", preset, "--size", "16x8", "--fps", "10", "--quiet", "--out", out};
        if (withTake) v.insert(v.end(), {"--replay", take});
        else v.insert(v.end(), {"--frames", "1"});
        return v;
    };
    const std::string a = FreshDir(root, "isf-scene-a"), b = FreshDir(root, "isf-scene-b"), c = FreshDir(root, "isf-scene-preset");
    const pid_t pa = Spawn(args(a, true), a + ".log"), pb = Spawn(args(b, true), b + ".log"), pc = Spawn(args(c, false), c + ".log");
    const int ra = WaitExit(pa, 60), rb = WaitExit(pb, 60), rc = WaitExit(pc, 60);
    INFO(ReadText(a + ".log") << ReadText(b + ".log") << ReadText(c + ".log"));
    REQUIRE(ra == 0);
    REQUIRE(rb == 0);
    REQUIRE(rc == 0);

    // The preset alone: level 1.5 of MAX 2, gain 2 of MAX 4 (a float with only MAX: 0..4).
    const std::array<int, 3> p = Pixel(c, 0);
    CHECK(std::abs(p[0] - 191) <= 1);
    CHECK(p[1] == 0);   // no audio: the spectrum is silent
    CHECK(std::abs(p[2] - 128) <= 1);
    // With the take (21 frames at 10 fps): byte-identical twice, and each event's value 0.4 s on.
    for (int i = 0; i <= 20; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "/frame_%05d.png", i);
        INFO(name);
        REQUIRE(ReadText(a + name) == ReadText(b + name));
    }
    CHECK(std::abs(Pixel(a, 0)[0] - 191) <= 1);
    CHECK(std::abs(Pixel(a, 9)[0] - 51) <= 3);
    CHECK(std::abs(Pixel(a, 14)[0] - 191) <= 3);
    CHECK(Pixel(a, 19)[0] == 255);
    CHECK(Pixel(a, 19)[2] == 0);

    // --param past MAX is clamped and said; an unknown input names the inputs there are.
    const std::string d = FreshDir(root, "isf-scene-param");
    REQUIRE(Run({SDFVJ_BIN, "render", "--scene", kGenerator, "--param", "level=9", "--frames", "1", "--size", "16x8", "--quiet",
                 "--out", d}, d + ".log", 60) == 0);
    CHECK(ReadText(d + ".log").find("level = 9 is outside [0, 2], clamped to 2") != std::string::npos);
    CHECK(Pixel(d, 0)[0] == 255);
    REQUIRE(Run({SDFVJ_BIN, "render", "--preset", preset, "--param", "nope=1", "--frames", "1", "--quiet", "--out", d},
                d + ".err", 60) == 2);
    CHECK(ReadText(d + ".err").find("has no parameter 'nope', expected one of: level, gain") != std::string::npos);
}
