// `sdfvj render --video` as a separate process against the real ffmpeg: no shell between us and
// ffmpeg (any character in the path), odd sizes padded for libx264, and a failed encode is a
// failed render (exit 1 with ffmpeg's status), never a silent 0 or a death by SIGPIPE.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "proc_util.h"

using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

bool HaveFfmpeg() {
    if (HaveTool("ffmpeg") && HaveTool("ffprobe")) return true;
    WARN("ffmpeg/ffprobe not installed: skipping the --video test (apt-get install ffmpeg)");
    return false;
}

// ffprobe's codec, size and frame count of the first video stream, "key=value" lines.
std::string Probe(const std::string& dir, const std::string& mp4) {
    int rc = Run({"ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                  "stream=codec_name,width,height,nb_read_frames", "-of", "default=noprint_wrappers=1", "file:" + mp4},
                 dir + "/ffprobe.txt", 30);
    return "rc=" + std::to_string(rc) + "\n" + ReadText(dir + "/ffprobe.txt");
}

int RenderVideo(const std::string& dir, const std::string& mp4, const std::string& size, int frames,
                const std::vector<EnvChange>& env = {}) {
    return Run({SDFVJ_BIN, "render", "--scene", "primitives", "--effects", "none", "--frames", std::to_string(frames),
                "--size", size, "--path", "fragment", "--quiet", "--video", mp4},
               dir + "/render.log", 60, env);
}

}  // namespace

TEST_CASE("replay video: an output path with a quote and spaces encodes (ffmpeg gets an argv, no shell)", "[video]") {
    if (!HaveFfmpeg()) return;
    const std::string dir = FreshDir(SDFVJ_REPLAY_OUT, "video-quote");
    const std::string mp4 = dir + "/it's a $HOME take.mp4";
    int rc = RenderVideo(dir, mp4, "64x48", 3);
    INFO(ReadText(dir + "/render.log"));
    REQUIRE(rc == 0);
    REQUIRE(fs::exists(mp4));
    CHECK(fs::file_size(mp4) > 0);
    const std::string probe = Probe(dir, mp4);
    INFO(probe);
    CHECK(probe.find("rc=0") != std::string::npos);
    CHECK(probe.find("codec_name=h264") != std::string::npos);
    CHECK(probe.find("nb_read_frames=3") != std::string::npos);
}

TEST_CASE("replay video: an odd size (161x91) is padded to even (162x92) for libx264", "[video]") {
    if (!HaveFfmpeg()) return;
    const std::string dir = FreshDir(SDFVJ_REPLAY_OUT, "video-odd");
    const std::string mp4 = dir + "/odd.mp4";
    int rc = RenderVideo(dir, mp4, "161x91", 2);
    INFO(ReadText(dir + "/render.log"));
    REQUIRE(rc == 0);
    const std::string probe = Probe(dir, mp4);
    INFO(probe);
    CHECK(probe.find("rc=0") != std::string::npos);
    CHECK(probe.find("width=162") != std::string::npos);
    CHECK(probe.find("height=92") != std::string::npos);
    CHECK(probe.find("nb_read_frames=2") != std::string::npos);
}

TEST_CASE("replay video: a failed encode (output folder missing) exits 1 with ffmpeg's exit status", "[video]") {
    if (!HaveFfmpeg()) return;
    const std::string dir = FreshDir(SDFVJ_REPLAY_OUT, "video-fail");
    const std::string mp4 = dir + "/no/such/folder/out.mp4";
    int rc = RenderVideo(dir, mp4, "64x48", 2);
    const std::string log = ReadText(dir + "/render.log");
    INFO(log);
    CHECK(rc == 1);
    CHECK(log.find("sdfvj render: ffmpeg") != std::string::npos);
    CHECK(log.find("exit status") != std::string::npos);
    CHECK_FALSE(fs::exists(mp4));
}

TEST_CASE("replay video: ffmpeg quitting mid-stream is reported (no death by SIGPIPE), exit 1", "[video]") {
    const std::string dir = FreshDir(SDFVJ_REPLAY_OUT, "video-quit");
    // A stand-in ffmpeg that reads nothing and exits 3: every frame after the pipe's buffer
    // (64 KiB, about 6 frames of 64x48 RGBA) meets a closed pipe.
    const std::string bin = dir + "/bin";
    fs::create_directories(bin);
    std::ofstream(bin + "/ffmpeg") << "#!/bin/sh\nexit 3\n";
    chmod((bin + "/ffmpeg").c_str(), 0755);
    const char* path = std::getenv("PATH");
    int rc = RenderVideo(dir, dir + "/out.mp4", "64x48", 24, {{"PATH", bin + ":" + (path ? path : "/usr/bin:/bin")}});
    const std::string log = ReadText(dir + "/render.log");
    INFO(log);
    CHECK(rc == 1);
    CHECK(log.find("ffmpeg stopped reading frames") != std::string::npos);
    CHECK(log.find("exit status 3") != std::string::npos);
}
