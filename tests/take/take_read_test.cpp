// Reading SMF files we did not write: format 1, tempo maps, running status, SMPTE, SysEx,
// unknown meta events and chunks; and malformed input with byte-exact messages.
#include <catch2/catch.hpp>

#include "take_test_util.h"

using namespace sdfvj;
using namespace take_test;

static TakeReadResult Parse(const std::vector<uint8_t>& bytes, Take* take) {
    return ParseTake(bytes.data(), bytes.size(), "take.mid", take);
}

static bool AnyContains(const std::vector<std::string>& lines, const std::string& part) {
    for (const std::string& l : lines)
        if (l.find(part) != std::string::npos) return true;
    return false;
}

// Format 1, 480 ticks per quarter. Tempo map (conductor track): 120 BPM, then 240 BPM at tick
// 960 (1.0 s), then 60 BPM at tick 1920 (1.0 + 960 * 0.25 / 480 = 1.5 s).
static std::vector<uint8_t> Format1File() {
    Bytes conductor;
    conductor({0x00, 0xFF, 0x58, 0x04, 4, 2, 24, 8})          // time signature: skipped
             ({0x00, 0xFF, 0x51, 0x03, 0x07, 0xA1, 0x20})      // 500000 us per quarter
             ({0x00, 0xF0, 0x05, 0x7E, 0x7F, 0x09, 0x01, 0xF7}) // SysEx (GM on): skipped
             ({0x87, 0x40, 0xFF, 0x51, 0x03, 0x03, 0xD0, 0x90}) // delta 960: 250000 us
             ({0x00, 0xFF, 0x60, 0x02, 0xAA, 0xBB})            // unknown meta type: skipped
             ({0x87, 0x40, 0xFF, 0x51, 0x03, 0x0F, 0x42, 0x40}) // delta 960: 1000000 us
             ({0x00, 0xFF, 0x2F, 0x00});
    Bytes strings;  // channel 2, running status throughout
    strings({0x00, 0x91, 0x3C, 0x64})        // tick 0: note on      -> 0.0 s
           ({0x83, 0x60, 0x3C, 0x00})        // tick 480: (running) note off -> 0.5 s
           ({0x87, 0x40, 0xB1, 0x07, 0x50})  // tick 1440: CC 7     -> 1.0 + 480 * 0.25 / 480 = 1.25 s
           ({0x87, 0x40, 0x07, 0x51})        // tick 2400: (running) CC 7 -> 1.5 + 480 / 480 = 2.5 s
           ({0x00, 0xFF, 0x2F, 0x00});
    Bytes drums;    // channel 10, program changes with running status, a text event
    drums({0x87, 0x40, 0xC9, 0x05})           // tick 960: program 5 -> 1.0 s
         ({0x87, 0x40, 0x06})                 // tick 1920: (running) program 6 -> 1.5 s
         ({0x00, 0xFF, 0x01, 0x03, 'h', 'i', '!'})
         ({0x8F, 0x00, 0xFF, 0x2F, 0x00});    // End-of-Track at tick 3840 -> 1.5 + 1920 / 480 = 5.5 s
    Bytes file;
    file.Header(1, 3, 480).Track(conductor.v).Track(strings.v).Track(drums.v);
    return file.v;
}

TEST_CASE("take: format 1 with tempo changes and running status reads with the right times", "[take]") {
    Take take;
    const TakeReadResult r = Parse(Format1File(), &take);
    REQUIRE(r.ok);
    CHECK(take.warnings.empty());
    REQUIRE(take.events.size() == 6);
    CHECK(SameMidi(take.events[0], {0x91, 0x3C, 0x64}));
    CHECK(take.events[0].time == 0.0);
    CHECK(SameMidi(take.events[1], {0x91, 0x3C, 0x00}));
    CHECK(take.events[1].time == Approx(0.5).margin(1e-12));
    CHECK(SameMidi(take.events[2], {0xC9, 0x05}));
    CHECK(take.events[2].time == Approx(1.0).margin(1e-12));
    CHECK(SameMidi(take.events[3], {0xB1, 0x07, 0x50}));
    CHECK(take.events[3].time == Approx(1.25).margin(1e-12));
    CHECK(SameMidi(take.events[4], {0xC9, 0x06}));
    CHECK(take.events[4].time == Approx(1.5).margin(1e-12));
    CHECK(SameMidi(take.events[5], {0xB1, 0x07, 0x51}));
    CHECK(take.events[5].time == Approx(2.5).margin(1e-12));
    CHECK(take.duration == Approx(5.5).margin(1e-12));
}

TEST_CASE("take: equal times across tracks keep track order", "[take]") {
    Bytes a, b, file;
    a({0x00, 0xB0, 0x01, 0x01})({0x00, 0xFF, 0x2F, 0x00});
    b({0x00, 0xB0, 0x02, 0x02})({0x00, 0xFF, 0x2F, 0x00});
    file.Header(1, 2, 96).Track(b.v).Track(a.v);
    Take take;
    REQUIRE(Parse(file.v, &take).ok);
    REQUIRE(take.events.size() == 2);
    CHECK(take.events[0].midi[1] == 0x02);
    CHECK(take.events[1].midi[1] == 0x01);
}

TEST_CASE("take: SMPTE division ignores tempo", "[take]") {
    Bytes track, file;
    track({0x00, 0xFF, 0x51, 0x03, 0x0F, 0x42, 0x40})  // tempo has no effect on SMPTE time
         ({0x83, 0x74, 0x90, 0x40, 0x40})              // tick 500 -> 0.5 s at 25 fps x 40
         ({0x83, 0x74, 0x40, 0x00})                    // tick 1000 -> 1.0 s
         ({0x00, 0xFF, 0x2F, 0x00});
    file.Header(0, 1, (0xE7 << 8) | 40);  // -25 fps, 40 ticks per frame
    file.Track(track.v);
    Take take;
    REQUIRE(Parse(file.v, &take).ok);
    REQUIRE(take.events.size() == 2);
    CHECK(take.events[0].time == 0.5);
    CHECK(take.events[1].time == 1.0);

    Bytes drop;
    drop.Header(0, 1, (0xE3 << 8) | 100).Track(track.v);  // -29: 29.97 drop-frame
    REQUIRE(Parse(drop.v, &take).ok);
    CHECK(take.events[0].time == Approx(500.0 / (30000.0 / 1001.0 * 100)));
}

TEST_CASE("take: unknown chunks are skipped, odd headers are read with warnings", "[take]") {
    Bytes track, file;
    track({0x00, 0x90, 0x40, 0x40})({0x00, 0xFF, 0x2F, 0x00});
    file.Str("MThd").U32(8)({0, 0, 0, 2, 0, 96, 0xAB, 0xCD});  // longer header, wrong track count
    file.Str("XFIH").U32(3)({1, 2, 3});                     // someone's private chunk
    file.Track(track.v);
    Take take;
    const TakeReadResult r = Parse(file.v, &take);
    REQUIRE(r.ok);
    CHECK(take.events.size() == 1);
    CHECK(AnyContains(take.warnings, "take.mid: byte 10: header declares 2 tracks"));
}

TEST_CASE("take: malformed files give take.mid: byte N errors", "[take]") {
    Take take;
    auto expectError = [&](const std::vector<uint8_t>& bytes, const std::string& part) {
        const TakeReadResult r = Parse(bytes, &take);
        INFO(r.error);
        CHECK_FALSE(r.ok);
        CHECK(r.error.find(part) != std::string::npos);
        CHECK(take.events.empty());
    };
    expectError({}, "take.mid: byte 0: not a Standard MIDI File");
    expectError(Bytes().Str("RIFF....").v, "take.mid: byte 0: not a Standard MIDI File");
    expectError(Bytes().Str("MThd")({0, 0, 0, 6, 0}).v, "take.mid: byte 9: header chunk cut short");
    expectError(Bytes().Str("MThd").U32(2)({0, 0, 0, 1, 0, 96}).v, "take.mid: byte 4: header length 2 is less than 6");
    expectError(Bytes().Str("MThd").U32(600)({0, 0, 0, 1, 0, 96}).v, "take.mid: byte 4: header length 600 runs past");
    expectError(Bytes().Header(0, 1, 0).v, "take.mid: byte 12: division is 0");
    expectError(Bytes().Header(0, 1, (0xEC << 8) | 4).v, "take.mid: byte 12: SMPTE division with 20 frames");
    expectError(Bytes().Header(0, 1, 96).v, "take.mid: byte 14: no track chunk");

    // Track data starts at byte 22.
    expectError(Bytes().Header(0, 1, 96).Track({0xFF, 0xFF, 0xFF, 0xFF, 0x7F, 0x90, 1, 1}).v,
                "take.mid: byte 22: delta time is a variable-length number longer than 4 bytes");
    expectError(Bytes().Header(0, 1, 96).Track({0x00, 0x90, 1, 1, 0x00, 0xFF, 0x01, 0x80, 0x80, 0x80, 0x80, 0x00}).v,
                "take.mid: byte 29: event length is a variable-length number");
    expectError(Bytes().Header(0, 1, 96).Track({0x00, 0x40, 0x40}).v,
                "take.mid: byte 23: data byte 0x40 with no status byte");
    expectError(Bytes().Header(0, 1, 96).Track({0x00, 0x90, 0x40, 0x40, 0x00, 0xF8}).v,
                "take.mid: byte 27: status byte 0xF8 cannot appear in a track");
    expectError(Bytes().Header(0, 1, 96).Track({0x00, 0x90, 0x40, 0x40, 0x00, 0xB0, 0x07, 0x90}).v,
                "take.mid: byte 29: data byte 0x90 has its top bit set");
}

TEST_CASE("take: files cut short read up to the cut with a warning", "[take]") {
    Take full;
    const std::vector<uint8_t> bytes = Format1File();
    REQUIRE(Parse(bytes, &full).ok);
    // Every prefix: a clean error before the first track, else the events up to the cut.
    for (size_t n = 0; n < bytes.size(); ++n) {
        std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + long(n));
        Take take;
        const TakeReadResult r = Parse(cut, &take);
        INFO("cut at " << n << ": " << r.error);
        if (n < 22) {
            CHECK_FALSE(r.ok);
            CHECK(r.error.rfind("take.mid: byte ", 0) == 0);
            continue;
        }
        REQUIRE(r.ok);
        CHECK_FALSE(take.warnings.empty());
        CHECK(take.events.size() <= full.events.size());
        for (const std::string& w : take.warnings) CHECK(w.rfind("take.mid: byte ", 0) == 0);
    }
    // A track chunk whose length runs past the end: warned at the length field (byte 18).
    std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + 40);
    Take take;
    REQUIRE(Parse(cut, &take).ok);
    CHECK(AnyContains(take.warnings, "take.mid: byte 18: track chunk length"));
}

TEST_CASE("take: a cut inside an event keeps the events before it", "[take]") {
    Bytes file;
    file.Header(0, 1, 96).Track({0x00, 0x90, 0x40, 0x40, 0x60, 0xB0, 0x07});  // second event cut
    Take take;
    const TakeReadResult r = Parse(file.v, &take);
    REQUIRE(r.ok);
    REQUIRE(take.events.size() == 1);
    CHECK(AnyContains(take.warnings, "take.mid: byte 26: track 1 is cut short in the middle of an event"));
}

TEST_CASE("take: junk OSC payloads and bytes after End-of-Track are warnings", "[take]") {
    Bytes track, file;
    track({0x00, 0xFF, 0x7F, 0x07, 0x7D, 'O', 'S', 'C', 0x01, 'x', 0})  // address without '/'
         ({0x00, 0xFF, 0x7F, 0x03, 0x00, 0x00, 0x41})                // someone else's FF 7F
         ({0x00, 0x90, 0x40, 0x40})
         ({0x00, 0xFF, 0x2F, 0x00})({0x12, 0x34});
    file.Header(0, 1, 96).Track(track.v);
    Take take;
    REQUIRE(Parse(file.v, &take).ok);
    CHECK(take.events.size() == 1);
    CHECK(AnyContains(take.warnings, "take.mid: byte 23: OSC event skipped: OSC address does not start with '/'"));
    CHECK(AnyContains(take.warnings, "bytes after the End-of-Track of track 1 ignored"));
}

TEST_CASE("take: ReadTake names the path and rejects missing files", "[take]") {
    Take take;
    const TakeReadResult r = ReadTake("/nonexistent/take.mid", &take);
    CHECK_FALSE(r.ok);
    CHECK(r.error.find("/nonexistent/take.mid") != std::string::npos);
}
