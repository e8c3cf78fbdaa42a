// The committed demo take (presets/demo_take.mid, preset `demo`) rendered in-process on the
// fixed clock (30 fps, fragment path, 160x90), compared at a few frame indices with committed
// reference PNGs in tests/replay/reference/.
//
// Tolerance (as tests/render): at most 0.2% of pixels may have a channel more than 8/255 off,
// and the mean channel difference must stay under 0.5/255. Regenerate after an intended change
// with SDFVJ_UPDATE_REFERENCES=1 (then look at the images before committing them).
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app/replay_driver.h"
#include "app/show.h"
#include "gl_fixture.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

TEST_CASE("replay reference: demo take frames match the committed references") {
    RequireGl();
    const bool update = std::getenv("SDFVJ_UPDATE_REFERENCES") != nullptr;
    const int kW = 160, kH = 90;
    const double fps = 30.0, dt = 1.0 / fps;
    const std::vector<int> indices = {0, 24, 60, 96, 132};

    ShowOptions opts;
    opts.preset = "demo";
    opts.path = "fragment";
    Show show;
    std::string error;
    REQUIRE(PrepareShow(opts, &show, &error));
    REQUIRE(BuildShow(&show, "fragment", &error, false));
    INFO(error);
    auto replay = MakeReplayDriver(show, "presets/demo_take.mid", "", &error);
    REQUIRE(replay);
    REQUIRE(replay->Duration() * fps >= indices.back());
    FrameRenderer fr;
    REQUIRE(fr.Resize(kW, kH, &error));

    FrameInputs in;
    in.quality = show.quality;
    in.params = show.params;
    fs::create_directories(SDFVJ_REPLAY_OUT);
    size_t next = 0;
    for (int i = 0; next < indices.size(); ++i) {
        // Same sequence as `sdfvj render`: every frame advances the take, only some are drawn.
        in.frame = i;
        in.time = i * dt;
        replay->Advance(in.time, dt, &in.params);
        if (i != indices[next]) continue;
        ++next;
        fr.Draw(*show.program, show.scene, in);
        Image actual{kW, kH, fr.ReadPixels()};
        char name[64];
        std::snprintf(name, sizeof name, "demo_take_%03d.png", i);
        const std::string refPath = std::string(SDFVJ_REPLAY_REFERENCE_DIR) + "/" + name;
        SavePng(std::string(SDFVJ_REPLAY_OUT) + "/" + name, actual);
        if (update) {
            REQUIRE(SavePng(refPath, actual));
            WARN("updated " << refPath);
            continue;
        }
        Image ref;
        INFO(refPath << " (regenerate with SDFVJ_UPDATE_REFERENCES=1; this run's image is in " << SDFVJ_REPLAY_OUT << ")");
        REQUIRE(LoadPng(refPath, &ref));
        REQUIRE(ref.width == kW);
        REQUIRE(ref.height == kH);
        ImageDiff d = CompareImages(actual, ref, 8);
        INFO("frame " << i << ": mean " << d.meanAbs << ", max " << d.maxAbs << ", over 8/255: "
                      << d.fractionOver * 100 << "%");
        CHECK(d.fractionOver <= 0.002);
        CHECK(d.meanAbs < 0.5);
    }
}
