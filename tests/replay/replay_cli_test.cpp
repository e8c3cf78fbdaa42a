// `sdfvj render --replay` through the command line, as separate processes: the same take renders
// byte-identical frames twice, and `--video` makes an H.264 file ffprobe agrees with.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>

#include "gl_fixture.h"
#include "proc_util.h"

using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

uint64_t Fnv1a(const std::vector<uint8_t>& bytes) {
    uint64_t h = 1469598103934665603ull;
    for (uint8_t b : bytes) { h ^= b; h *= 1099511628211ull; }
    return h;
}

// Hash of every frame's decoded pixels, in frame order.
std::vector<uint64_t> FrameHashes(const std::string& dir, int frames) {
    std::vector<uint64_t> hashes;
    for (int i = 0; i < frames; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "frame_%05d.png", i);
        Image img;
        INFO((fs::path(dir) / name).string());
        REQUIRE(LoadPng((fs::path(dir) / name).string(), &img));
        REQUIRE(img.width == 96);
        REQUIRE(img.height == 54);
        hashes.push_back(Fnv1a(img.rgba));
    }
    return hashes;
}

}  // namespace

TEST_CASE("replay determinism: the demo take renders byte-identical frames twice (CLI, 30 frames)") {
    const std::string root = SDFVJ_REPLAY_OUT;
    std::string a = FreshDir(root, "determinism-a"), b = FreshDir(root, "determinism-b");
    std::string c = FreshDir(root, "determinism-no-take");
    auto args = [](const std::string& out, bool take) {
        std::vector<std::string> v = {SDFVJ_BIN, "render", "--preset", "demo", "--frames", "30", "--size", "96x54",
                                      "--path", "fragment", "--quiet", "--param", "spin=0", "--out", out};
        if (take) v.insert(v.end(), {"--replay", "presets/demo_take.mid"});
        return v;
    };
    // All runs at once: each is its own process, GL context and compile. The third renders the
    // preset without the take, to see what the take changes.
    pid_t pa = Spawn(args(a, true), a + ".log"), pb = Spawn(args(b, true), b + ".log");
    pid_t pc = Spawn(args(c, false), c + ".log");
    int ra = WaitExit(pa, 60), rb = WaitExit(pb, 60), rc = WaitExit(pc, 60);
    INFO(ReadText(a + ".log") << ReadText(b + ".log") << ReadText(c + ".log"));
    REQUIRE(ra == 0);
    REQUIRE(rb == 0);
    REQUIRE(rc == 0);
    CHECK_FALSE(fs::exists(fs::path(a) / "frame_00030.png"));   // --frames 30 means 30

    std::vector<uint64_t> ha = FrameHashes(a, 30), hb = FrameHashes(b, 30);
    for (int i = 0; i < 30; ++i) {
        INFO("frame " << i);
        CHECK(ha[i] == hb[i]);
    }
    // The frames are not all alike ...
    std::set<uint64_t> distinct(ha.begin(), ha.end());
    INFO(distinct.size() << " distinct frames of 30");
    CHECK(distinct.size() >= 8);
    // ... and the take itself changes them: its knob sweeps (CC 1-4 from t=0) must reach the
    // scene through the preset's mapping, so most frames differ from the preset without the take.
    std::vector<uint64_t> hc = FrameHashes(c, 30);
    int changed = 0;
    for (int i = 0; i < 30; ++i) changed += ha[i] != hc[i];
    INFO(changed << " of 30 frames differ from the same preset rendered without the take "
                    "(0 means the take's controls are not in the preset's mapping)");
    CHECK(changed >= 20);
}

TEST_CASE("replay video: --video pipes frames to ffmpeg, ffprobe reads 10 frames of 96x54 h264") {
    if (!HaveTool("ffmpeg") || !HaveTool("ffprobe")) {
        WARN("ffmpeg/ffprobe not installed: skipping the --video test (apt-get install ffmpeg)");
        return;
    }
    const std::string dir = FreshDir(SDFVJ_REPLAY_OUT, "video");
    const std::string mp4 = dir + "/out.mp4";
    int rc = Run({SDFVJ_BIN, "render", "--scene", "midi", "--frames", "10", "--size", "96x54", "--path", "fragment",
                  "--quiet", "--video", mp4},
                 dir + "/render.log", 60);
    INFO(ReadText(dir + "/render.log"));
    REQUIRE(rc == 0);
    REQUIRE(fs::exists(mp4));
    REQUIRE(fs::file_size(mp4) > 0);
    rc = Run({"ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
              "stream=codec_name,width,height,nb_read_frames", "-of", "default=noprint_wrappers=1", mp4},
             dir + "/ffprobe.txt", 30);
    const std::string probe = ReadText(dir + "/ffprobe.txt");
    INFO(probe);
    REQUIRE(rc == 0);
    CHECK(probe.find("codec_name=h264") != std::string::npos);
    CHECK(probe.find("width=96") != std::string::npos);
    CHECK(probe.find("height=54") != std::string::npos);
    CHECK(probe.find("nb_read_frames=10") != std::string::npos);
}

TEST_CASE("replay determinism: a scripted preset (LFOs on the beat) renders the same bytes twice, with and without a take") {
    const std::string root = SDFVJ_REPLAY_OUT;
    std::string a = FreshDir(root, "scripted-a"), b = FreshDir(root, "scripted-b"), c = FreshDir(root, "scripted-c");
    auto args = [](const std::string& out, bool take) {
        std::vector<std::string> v = {SDFVJ_BIN, "render", "--preset", "pulse", "--frames", "12", "--fps", "4", "--size",
                                      "96x54", "--path", "fragment", "--quiet", "--param", "spin=0", "--out", out};
        if (take) v.insert(v.end(), {"--replay", "presets/demo_take.mid", "--mapping", "mappings/akai_lpd8.toml"});
        return v;
    };
    pid_t pa = Spawn(args(a, true), a + ".log"), pb = Spawn(args(b, true), b + ".log");
    pid_t pc = Spawn(args(c, false), c + ".log");
    int ra = WaitExit(pa, 60), rb = WaitExit(pb, 60), rc = WaitExit(pc, 60);
    INFO(ReadText(a + ".log") << ReadText(b + ".log") << ReadText(c + ".log"));
    REQUIRE(ra == 0);
    REQUIRE(rb == 0);
    REQUIRE(rc == 0);
    const std::vector<uint64_t> ha = FrameHashes(a, 12), hb = FrameHashes(b, 12), hc = FrameHashes(c, 12);
    CHECK(ha == hb);                                   // same bytes every time
    // The LFOs move the picture with no take at all (spin is 0: only automation changes it).
    CHECK(std::set<uint64_t>(hc.begin(), hc.end()).size() >= 10);
}
