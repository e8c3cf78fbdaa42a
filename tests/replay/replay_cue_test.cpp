// `sdfvj render --preset P` follows a cue that switches to another preset on another scene: the
// frames before the cue are P's scene, a crossfade over the new preset's morph time follows, then
// the new preset's scene; and the run renders the same bytes twice. The presets live in a data
// root of the test's own (SDFVJ_ROOT: shaders/ and mappings/ linked from the source tree).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "gl_fixture.h"
#include "proc_util.h"

using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

// A data root with presets a (midi at 240 bpm, a cue at bar 1 = 1 s to b), a_still (a without
// the cue), b (primitives, crossfades in over 0.5 s, linear), a_field and b_field (the same with
// the fields morphing).
// Each test has its own (ctest runs them in parallel).
std::string CueRoot(const std::string& name) {
    const std::string root = FreshDir(SDFVJ_REPLAY_OUT, name);
    for (const char* d : {"shaders", "mappings"}) fs::create_directory_symlink(fs::path(SDFVJ_SOURCE_ROOT) / d, fs::path(root) / d);
    fs::create_directory(fs::path(root) / "presets");
    auto write = [&](const char* name, const std::string& text) { std::ofstream(fs::path(root) / "presets" / name) << text; };
    const std::string a = R"({"scene": "midi", "bpm": 240, "params": {"spin": 0, "twist": 0.0}, "effects": "none")";
    write("a.json", a + R"(, "cues": [{"bar": 1, "preset": "b"}]})");
    write("a_still.json", a + "}");
    write("b.json", R"({"scene": "primitives", "params": {"spin": 0, "bob": 0}, "effects": "none",
                       "morph": {"seconds": 0.5, "easing": "linear", "scenes": "crossfade"}})");
    // The same switch with the default scene morph: the two fields in one program.
    write("a_field.json", a + R"(, "cues": [{"bar": 1, "preset": "b_field"}]})");
    write("b_field.json", R"({"scene": "primitives", "params": {"spin": 0, "bob": 0}, "effects": "none",
                             "morph": {"seconds": 0.5, "easing": "linear"}})");
    return root;
}

// Renders `preset` for 8 frames at 4 fps (frame 4 is at 1 s) into a fresh folder; returns it.
std::string Render(const std::string& root, const std::string& preset, const std::string& name) {
    const std::string out = FreshDir(SDFVJ_REPLAY_OUT, name);
    const int rc = Run({SDFVJ_BIN, "render", "--preset", preset, "--frames", "8", "--fps", "4", "--size", "96x54",
                        "--path", "fragment", "--out", out, "--quiet"},
                       out + ".log", 120, {{"SDFVJ_ROOT", root}});
    INFO(ReadText(out + ".log"));
    REQUIRE(rc == 0);
    return out;
}

Image Frame(const std::string& dir, int i) {
    char name[64];
    std::snprintf(name, sizeof name, "frame_%05d.png", i);
    Image img;
    INFO((fs::path(dir) / name).string());
    REQUIRE(LoadPng((fs::path(dir) / name).string(), &img));
    return img;
}

std::string Bytes(const std::string& path) { return ReadText(path); }

}  // namespace

TEST_CASE("replay cues: render --preset follows a cue to another preset and scene, crossfading over its morph time") {
    const std::string root = CueRoot("cue-root1");
    const std::string run1 = Render(root, "a", "cue-run1"), run2 = Render(root, "a", "cue-run2");
    const std::string still = Render(root, "a_still", "cue-a-still"), b = Render(root, "b", "cue-b");
    const std::string log = ReadText(run1 + ".log");
    INFO(log);
    CHECK(log.find("cue at 1.000 s: preset b.json (primitives)") != std::string::npos);
    CHECK(log.find("does not follow") == std::string::npos);

    // The same bytes twice: every PNG file of the two runs.
    for (int i = 0; i < 8; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "/frame_%05d.png", i);
        INFO("frame " << i);
        CHECK(Bytes(run1 + name) == Bytes(run2 + name));
    }
    // Before the cue and at it (the fade starts at 0): preset a's scene. Exact: the same program,
    // values and clock.
    for (int i : {0, 3, 4}) {
        INFO("frame " << i);
        CHECK(CompareImages(Frame(run1, i), Frame(still, i), 0).maxAbs == 0);
    }
    // Half way through the 0.5 s fade (frame 5, 0.25 s in, linear): the average of the two scenes'
    // frames, within 8-bit rounding (each side is rounded once, the mix once more).
    const Image mid = Frame(run1, 5), from = Frame(still, 5), to = Frame(b, 5);
    int worst = 0;
    for (size_t k = 0; k < mid.rgba.size(); ++k) {
        if (k % 4 == 3) continue;
        const double expected = 0.5 * (from.rgba[k] + to.rgba[k]);
        worst = std::max(worst, (int)std::ceil(std::abs(mid.rgba[k] - expected)));
    }
    CHECK(worst <= 2);
    CHECK(CompareImages(mid, from, 8).fractionOver > 0.05);   // and it is neither scene alone
    CHECK(CompareImages(mid, to, 8).fractionOver > 0.05);
    // After the fade: preset b's scene, as b renders it on its own (its values are static; the
    // tempo the cue keeps, 240 bpm, moves nothing in it).
    for (int i : {6, 7}) {
        const ImageDiff d = CompareImages(Frame(run1, i), Frame(b, i), 0);
        INFO("frame " << i << ": mean " << d.meanAbs << " max " << d.maxAbs);
        CHECK(d.maxAbs == 0);
    }
}

TEST_CASE("replay cues: a cue to a preset that does not exist is reported with its line and the show goes on") {
    const std::string root = CueRoot("cue-root2");
    std::ofstream(fs::path(root) / "presets" / "a.json")
        << R"({"scene": "midi", "bpm": 240, "params": {"spin": 0}, "effects": "none",
  "cues": [{"bar": 1, "preset": "no_such_preset"}]})";
    const std::string out = Render(root, "a", "cue-missing");
    const std::string log = ReadText(out + ".log");
    INFO(log);
    CHECK(log.find("a.json:2: cue preset 'no_such_preset' does not exist") != std::string::npos);
    CHECK(fs::exists(out + "/frame_00007.png"));
}

TEST_CASE("replay cues: a cue to another scene morphs the two fields in render as in live, the same bytes every run") {
    const std::string root = CueRoot("cue-root3");
    const std::string run1 = Render(root, "a_field", "cue-field1"), run2 = Render(root, "a_field", "cue-field2");
    const std::string still = Render(root, "a_still", "cue-field-a"), b = Render(root, "b", "cue-field-b");
    INFO(ReadText(run1 + ".log"));
    CHECK(ReadText(run1 + ".log").find("cannot morph") == std::string::npos);
    for (int i = 0; i < 8; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "/frame_%05d.png", i);
        INFO("frame " << i);
        CHECK(Bytes(run1 + name) == Bytes(run2 + name));
    }
    for (int i : {0, 3}) CHECK(CompareImages(Frame(run1, i), Frame(still, i), 0).maxAbs == 0);
    // Half way: a third picture, neither scene and not the average of their frames.
    const Image mid = Frame(run1, 5), from = Frame(still, 5), to = Frame(b, 5);
    Image avg = from;
    for (size_t k = 0; k < avg.rgba.size(); ++k) avg.rgba[k] = (uint8_t)((from.rgba[k] + to.rgba[k] + 1) / 2);
    CHECK(CompareImages(mid, from, 8).fractionOver > 0.05);
    CHECK(CompareImages(mid, to, 8).fractionOver > 0.05);
    CHECK(CompareImages(mid, avg, 16).fractionOver > 0.05);
    for (int i : {6, 7}) CHECK(CompareImages(Frame(run1, i), Frame(b, i), 0).maxAbs == 0);
}
