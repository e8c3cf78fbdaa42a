// `sdfvj render --frame-range A:B` renders frames A..B exactly as the whole render does: the
// PNG files of slices are byte-identical (cmp) to the same frames of one run, for a take that
// moves knobs through a smoothed mapping, and for a scripted preset whose cue switches presets
// and crossfades scenes (a slice starting mid-fade). Files keep their absolute frame index.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "proc_util.h"

using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

std::string FrameName(int i) {
    char name[64];
    std::snprintf(name, sizeof name, "frame_%05d.png", i);
    return name;
}

// Bytes of a file; "" (and a failed CHECK) when it is missing.
std::string FileBytes(const std::string& path) {
    INFO(path);
    CHECK(fs::exists(path));
    return ReadText(path);
}

// Renders with `args` plus --out into a fresh folder named `name`; returns the folder.
std::string Render(std::vector<std::string> args, const std::string& name, const std::vector<EnvChange>& env = {}) {
    const std::string out = FreshDir(SDFVJ_REPLAY_OUT, name);
    fs::remove(out + ".log");
    args.insert(args.begin(), {SDFVJ_BIN, "render"});
    args.insert(args.end(), {"--size", "96x54", "--path", "fragment", "--quiet", "--out", out});
    const int rc = Run(args, out + ".log", 120, env);
    INFO(ReadText(out + ".log"));
    REQUIRE(rc == 0);
    return out;
}

// Every frame of each slice equals the whole render's frame byte for byte, and a slice holds
// nothing else.
void CheckSlices(const std::string& whole, int frames, const std::vector<std::pair<std::string, std::pair<int, int>>>& slices) {
    int covered = 0;
    for (const auto& [dir, range] : slices) {
        for (int i = range.first; i <= range.second; ++i) {
            INFO("frame " << i << " of slice " << range.first << ":" << range.second);
            const std::string a = FileBytes(whole + "/" + FrameName(i)), b = FileBytes(dir + "/" + FrameName(i));
            CHECK(!a.empty());
            CHECK(a == b);
            ++covered;
        }
        int files = 0;
        for (const auto& e : fs::directory_iterator(dir)) files += e.path().extension() == ".png";
        CHECK(files == range.second - range.first + 1);
    }
    CHECK(covered == frames);
}

}  // namespace

TEST_CASE("replay range: slices of a take through a smoothed mapping equal the whole render byte for byte") {
    // demo + its take: CC sweeps every 10 ms through akai_lpd8 (smoothing 0.05-0.08 s), notes at
    // 1 s and 3 s; at 10 fps a slice starts while the knobs glide.
    const std::vector<std::string> base = {"--preset", "demo", "--replay", "presets/demo_take.mid", "--frames", "32", "--fps", "10"};
    auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> v = base;
        v.insert(v.end(), extra.begin(), extra.end());
        return v;
    };
    const std::string whole = Render(base, "range-take-whole");
    const std::string s1 = Render(with({"--frame-range", "0:6"}), "range-take-0-6");
    const std::string s2 = Render(with({"--frame-range", "7:13"}), "range-take-7-13");
    const std::string s3 = Render(with({"--frame-range", "14:"}), "range-take-14-end");
    CheckSlices(whole, 32, {{s1, {0, 6}}, {s2, {7, 13}}, {s3, {14, 31}}});
    // The take moves the picture: a slice that started from the preset's values would differ.
    CHECK(ReadText(whole + "/" + FrameName(7)) != ReadText(whole + "/" + FrameName(14)));
    CHECK(ReadText(whole + "/" + FrameName(14)) != ReadText(whole + "/" + FrameName(31)));
}

TEST_CASE("replay range: slices of a scripted preset whose cue switches presets equal the whole render, a slice starting mid-crossfade") {
    // A data root of the test's own: a (midi, 240 bpm, an LFO on twist, a cue at bar 1 = 1 s to
    // b on another scene) and b (crossfades in over 0.5 s).
    const std::string root = FreshDir(SDFVJ_REPLAY_OUT, "range-cue-root");
    for (const char* d : {"shaders", "mappings"}) fs::create_directory_symlink(fs::path(SDFVJ_SOURCE_ROOT) / d, fs::path(root) / d);
    fs::create_directory(fs::path(root) / "presets");
    std::ofstream(fs::path(root) / "presets" / "a.json")
        << R"json({"scene": "midi", "bpm": 240, "params": {"spin": 0, "twist": "0.5 * lfo_sine(beat / 2)"}, "effects": "none",
              "cues": [{"bar": 1, "preset": "b"}]})json";
    std::ofstream(fs::path(root) / "presets" / "b.json")
        << R"({"scene": "primitives", "params": {"spin": 0, "bob": 0}, "effects": "none",
              "morph": {"seconds": 0.5, "easing": "linear", "scenes": "crossfade"}})";
    const std::vector<EnvChange> env = {{"SDFVJ_ROOT", root}};
    // 12 frames at 8 fps: the cue at frame 8 (1 s), the fade until frame 12.
    const std::vector<std::string> base = {"--preset", "a", "--frames", "12", "--fps", "8"};
    auto with = [&](const std::string& range) {
        std::vector<std::string> v = base;
        v.insert(v.end(), {"--frame-range", range});
        return v;
    };
    const std::string whole = Render(base, "range-cue-whole", env);
    INFO(ReadText(whole + ".log"));
    const std::string s1 = Render(with("0:3"), "range-cue-0-3", env);
    const std::string s2 = Render(with("4:8"), "range-cue-4-8", env);
    const std::string s3 = Render(with("9:11"), "range-cue-9-11", env);   // starts mid-fade
    CheckSlices(whole, 12, {{s1, {0, 3}}, {s2, {4, 8}}, {s3, {9, 11}}});
    CHECK(ReadText(s3 + ".log").find("cue at 1.000 s: preset b.json (primitives)") != std::string::npos);
    // The fade is under way at frame 9 and the LFO moves frames 1..3.
    CHECK(ReadText(whole + "/" + FrameName(9)) != ReadText(whole + "/" + FrameName(11)));
    CHECK(ReadText(whole + "/" + FrameName(1)) != ReadText(whole + "/" + FrameName(3)));
}

TEST_CASE("replay range: a bad --frame-range is one line with what was expected, exit 2") {
    struct Case { std::string range, expect; };
    for (const Case& c : {Case{"5:2", "no frames in it"}, Case{"x:3", "expected A:B or A:"}, Case{"40:", "no frames in it"},
                          Case{"3", "expected A:B or A:"}}) {
        INFO(c.range);
        const std::string out = FreshDir(SDFVJ_REPLAY_OUT, "range-bad");
        fs::remove(out + ".log");
        const int rc = Run({SDFVJ_BIN, "render", "--scene", "midi", "--frames", "30", "--size", "32x18", "--quiet",
                            "--frame-range", c.range, "--out", out},
                           out + ".log", 30);
        const std::string log = ReadText(out + ".log");
        INFO(log);
        CHECK(rc == 2);
        CHECK(log.find(c.expect) != std::string::npos);
    }
}

TEST_CASE("replay range: --count-frames prints the whole render's length (the take's, else --frames)") {
    const std::string out = FreshDir(SDFVJ_REPLAY_OUT, "range-count");
    const int rc = Run({SDFVJ_BIN, "render", "--preset", "demo", "--replay", "presets/demo_take.mid", "--fps", "10", "--count-frames"},
                       out + "/count.txt", 30);
    REQUIRE(rc == 0);
    // The demo take lasts 8 s and some: ceil(duration * 10) + 1 frames.
    const int n = std::stoi(ReadText(out + "/count.txt"));
    CHECK(n >= 81);
    CHECK(n <= 92);
}
