// scripts/render_farm.sh on this machine: four slices run by GNU parallel and joined give the
// same PNG bytes as a one-machine render, and --video joins four H.264 segments into one file
// with every frame (ffprobe counts them).
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "proc_util.h"

using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kRenderArgs = {"--frames", "24", "--fps", "10", "--size", "96x54", "--path", "fragment"};

std::vector<std::string> FarmArgs(const std::vector<std::string>& dest) {
    std::vector<std::string> v = {"bash", std::string(SDFVJ_SOURCE_ROOT) + "/scripts/render_farm.sh", "presets/demo_take.mid",
                                  "--preset", "demo", "--slices", "4", "--jobs", "2", "--bin", SDFVJ_BIN};
    v.insert(v.end(), dest.begin(), dest.end());
    v.push_back("--");
    v.insert(v.end(), kRenderArgs.begin(), kRenderArgs.end());
    return v;
}

}  // namespace

TEST_CASE("replay farm: render_farm.sh with four slices joins PNGs byte-identical to a one-machine render") {
    const std::string whole = FreshDir(SDFVJ_REPLAY_OUT, "farm-whole"), farm = FreshDir(SDFVJ_REPLAY_OUT, "farm-png");
    fs::remove(whole + ".log");
    fs::remove(farm + ".log");
    std::vector<std::string> one = {SDFVJ_BIN, "render", "--preset", "demo", "--replay", "presets/demo_take.mid", "--quiet", "--out", whole};
    one.insert(one.end(), kRenderArgs.begin(), kRenderArgs.end());
    const int rcWhole = Run(one, whole + ".log", 120);
    INFO(ReadText(whole + ".log"));
    REQUIRE(rcWhole == 0);
    const int rcFarm = Run(FarmArgs({"--out", farm}), farm + ".log", 240);
    const std::string log = ReadText(farm + ".log");
    INFO(log);
    REQUIRE(rcFarm == 0);
    CHECK(log.find("24 frames in 4 slices") != std::string::npos);

    int files = 0;
    for (const auto& e : fs::directory_iterator(farm)) files += e.path().extension() == ".png";
    CHECK(files == 24);
    for (int i = 0; i < 24; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "/frame_%05d.png", i);
        INFO("frame " << i);
        const std::string a = ReadText(whole + name), b = ReadText(farm + name);
        CHECK(!a.empty());
        CHECK(a == b);
    }
    CHECK(!fs::exists(farm + ".slices"));   // the work folder is removed after the join
}

TEST_CASE("replay farm: render_farm.sh --video joins four segments into one video with every frame") {
    const std::string dir = FreshDir(SDFVJ_REPLAY_OUT, "farm-video");
    const std::string video = dir + "/farm.mp4";
    const int rc = Run(FarmArgs({"--video", video}), dir + "/farm.log", 240);
    INFO(ReadText(dir + "/farm.log"));
    REQUIRE(rc == 0);
    REQUIRE(fs::exists(video));
    const int probe = Run({"ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                           "stream=nb_read_frames,width,height", "-of", "default=noprint_wrappers=1", video},
                          dir + "/probe.txt", 60);
    const std::string info = ReadText(dir + "/probe.txt");
    INFO(info);
    REQUIRE(probe == 0);
    CHECK(info.find("nb_read_frames=24") != std::string::npos);
    CHECK(info.find("width=96") != std::string::npos);
}

TEST_CASE("replay farm: render_farm.sh refuses --frame-range (the farm sets it) with one line, exit 2") {
    const std::string dir = FreshDir(SDFVJ_REPLAY_OUT, "farm-bad");
    const int rc = Run({"bash", std::string(SDFVJ_SOURCE_ROOT) + "/scripts/render_farm.sh", "--preset", "demo", "--bin", SDFVJ_BIN,
                        "--frame-range", "0:3", "--out", dir + "/x"},
                       dir + "/log.txt", 30);
    const std::string log = ReadText(dir + "/log.txt");
    INFO(log);
    CHECK(rc == 2);
    CHECK(log.find("--frame-range is the farm's to set") != std::string::npos);
}
