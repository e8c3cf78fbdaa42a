// `--replay` takes any Standard MIDI File, not only our own takes: a hand-built format-1 file
// with two tracks (a conductor track with a tempo change, a controller track with running
// status, notes and a second channel) drives the `midi` scene through MakeReplayDriver and the
// generic 8-knob mapping (knobs 1-4 = CC 20-23 -> scale, twist, displacement, smoothness, each
// over the parameter's declared range, linear; smoothing 0.05 s, 0.08 s for smoothness).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>

#include "app/replay_driver.h"
#include "app/show.h"
#include "take/take.h"

using namespace sdfvj;
namespace fs = std::filesystem;

namespace {

void Chunk(std::vector<uint8_t>* out, const char* id, const std::vector<uint8_t>& body) {
    out->insert(out->end(), id, id + 4);
    const uint32_t n = (uint32_t)body.size();
    for (int s = 24; s >= 0; s -= 8) out->push_back((uint8_t)(n >> s));
    out->insert(out->end(), body.begin(), body.end());
}

// Division 480 ticks per quarter. Tempo 120 BPM (0.5 s per quarter) until tick 960 (= 1.0 s),
// then 240 BPM (0.25 s per quarter). So tick 1440 = 1.25 s, 1920 = 1.5 s, 2400 = 1.75 s;
// a reader that ignored the tempo change would put them at 1.5, 2.0 and 2.5 s.
std::vector<uint8_t> TwoTrackSmf() {
    std::vector<uint8_t> f;
    Chunk(&f, "MThd", {0x00, 0x01, 0x00, 0x02, 0x01, 0xE0});   // format 1, 2 tracks, 480 tpq
    Chunk(&f, "MTrk", {
        0x00, 0xFF, 0x51, 0x03, 0x07, 0xA1, 0x20,             // t=0    tempo 500000 us/quarter
        0x87, 0x40, 0xFF, 0x51, 0x03, 0x03, 0xD0, 0x90,       // t=960  tempo 250000 us/quarter
        0x00, 0xFF, 0x2F, 0x00,                               // end of track
    });
    Chunk(&f, "MTrk", {
        0x00, 0xFF, 0x03, 0x05, 'k', 'n', 'o', 'b', 's',      // track name (meta, ignored)
        0x00, 0xB0, 0x14, 0x7F,                               // t=0     ch1 CC20 = 127  (scale -> max)
        0x83, 0x60, 0x15, 0x00,                               // t=480   running status: CC21 = 0 (twist -> min)
        0x87, 0x40, 0x16, 0x7F,                               // t=1440  running status: CC22 = 127 (displacement -> max)
        0x00, 0x90, 0x3C, 0x40,                               // t=1440  note on 60 (not mapped)
        0x81, 0x70, 0x3C, 0x00,                               // t=1680  running status: note on vel 0
        0x81, 0x70, 0xB1, 0x17, 0x00,                         // t=1920  ch2 CC23 = 0 (smoothness -> min)
        0x83, 0x60, 0x14, 0x00,                               // t=2400  running status: ch2 CC20 = 0 (scale -> min)
        0x00, 0xFF, 0x2F, 0x00,
    });
    return f;
}

}  // namespace

TEST_CASE("replay any SMF: format 1, two tracks, tempo change, running status drive the mapping") {
    const std::vector<uint8_t> bytes = TwoTrackSmf();
    fs::create_directories(SDFVJ_REPLAY_OUT);
    const std::string path = std::string(SDFVJ_REPLAY_OUT) + "/two_track.mid";
    {
        std::ofstream f(path, std::ios::binary | std::ios::trunc);
        f.write((const char*)bytes.data(), (std::streamsize)bytes.size());
    }

    SECTION("the reader merges the tracks on the tempo map") {
        Take take;
        TakeReadResult r = ReadTake(path, &take);
        INFO(r.error);
        REQUIRE(r.ok);
        REQUIRE(take.events.size() == 7);
        const double want[] = {0.0, 0.5, 1.25, 1.25, 1.375, 1.5, 1.75};
        for (size_t i = 0; i < 7; ++i) {
            INFO("event " << i);
            CHECK(take.events[i].source == EventSource::Midi);
            CHECK(take.events[i].time == Approx(want[i]).margin(1e-6));
        }
        CHECK(take.events[1].midi[0] == 0xB0);   // running status resolved
        CHECK(take.events[1].midi[1] == 21);
        CHECK(take.events[4].midi[0] == 0x90);
        CHECK(take.events[4].midi[2] == 0);
        CHECK(take.events[6].midi[0] == 0xB1);
        CHECK(take.events[6].midi[1] == 20);
        CHECK(take.duration == Approx(1.75).margin(1e-6));
    }

    SECTION("parameter values at given times, through the generic mapping") {
        ShowOptions opts;
        opts.scene = "midi";
        Show show;
        std::string error;
        REQUIRE(PrepareShow(opts, &show, &error));
        auto driver = MakeReplayDriver(show, path, "mappings/generic_8knob.toml", &error);
        INFO(error);
        REQUIRE(driver);
        CHECK(driver->Duration() == Approx(1.75).margin(1e-6));

        // 100 fps fixed clock; record every frame's values by name.
        std::map<int, std::map<std::string, float>> at;   // frame index (time * 100) -> values
        std::vector<std::pair<std::string, float>> params;
        const double dt = 0.01;
        for (int i = 0; i <= 230; ++i) {
            driver->Advance(i * dt, dt, &params);
            for (const auto& [n, v] : params) at[i][n] = v;
        }
        // Scene defaults (shaders/scenes/midi.glsl): scale 1 [0.25, 2], twist 0.5 [-3, 3],
        // displacement 0.04 [0, 0.25], smoothness 0.35 [0, 1]. Untouched values stay exact.
        CHECK(at[0]["scale"] > 1.0f);                        // CC20 at t=0 applies to frame 0
        CHECK(at[40]["scale"] == Approx(2.0).margin(2e-3));  // 0.4 s = 8 time constants
        CHECK(at[49]["twist"] == 0.5f);                      // CC21 not before 0.5 s
        CHECK(at[51]["twist"] < 0.5f);
        CHECK(at[120]["twist"] == Approx(-3.0).margin(1e-3));
        CHECK(at[124]["displacement"] == 0.04f);             // CC22 at 1.25 s (tempo change honoured) ...
        CHECK(at[126]["displacement"] > 0.04f);
        CHECK(at[145]["displacement"] == Approx(0.25 - 0.21 * std::exp(-0.2 / 0.05)).margin(2e-3));  // ... not at 1.5 s
        CHECK(at[149]["smoothness"] == 0.35f);               // CC23 (channel 2) at 1.5 s, not 2.0 s
        CHECK(at[174]["smoothness"] == Approx(0.35 * std::exp(-0.24 / 0.08)).margin(3e-3));
        CHECK(at[174]["scale"] == Approx(2.0).margin(1e-3)); // second CC20 not before 1.75 s
        CHECK(at[230]["scale"] == Approx(0.25).margin(2e-3));// running status on channel 2
        CHECK(at[230]["smoothness"] == Approx(0.0).margin(2e-3));
        CHECK(at[230]["spin"] == 0.3f);                      // knob 5 never moved
    }
}
