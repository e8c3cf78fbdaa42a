// MIDI Time Code as pure code (control/mtc.h): quarter frames and full frames from byte
// sequences at all four rates, 8 quarter frames assembling a time forwards and backwards, and the
// show clock that follows the master across a seek, a locate (stop) and a dropout.
#include <catch2/catch.hpp>

#include <vector>

#include "control/control.h"
#include "control/mtc.h"

using namespace sdfvj;

namespace {

Timecode Tc(int h, int m, int s, int f, MtcRate rate) {
    Timecode tc;
    tc.hours = h;
    tc.minutes = m;
    tc.seconds = s;
    tc.frames = f;
    tc.rate = rate;
    return tc;
}

// Feeds "F1 dd" pairs; returns the times that became whole.
std::vector<Timecode> Feed(MtcReader& r, const std::vector<uint8_t>& bytes, std::vector<double>* seconds = nullptr) {
    std::vector<Timecode> out;
    for (size_t i = 0; i + 1 < bytes.size(); i += 2) {
        REQUIRE(bytes[i] == 0xF1);
        Timecode tc;
        double at = 0;
        if (MtcQuarterFrame(r, bytes[i + 1], &tc, &at)) {
            out.push_back(tc);
            if (seconds) seconds->push_back(at);
        }
    }
    return out;
}

}  // namespace

TEST_CASE("mtc: quarter frames of a hand-written byte sequence assemble 01:02:03:04 at 25 fps") {
    // Pieces 0..7: frames 4 (lo 4, hi 0), seconds 3, minutes 2, hours 1, rate 25 (01) -> piece 7 = 0b0010.
    const std::vector<uint8_t> bytes = {0xF1, 0x04, 0xF1, 0x10, 0xF1, 0x23, 0xF1, 0x30,
                                        0xF1, 0x42, 0xF1, 0x50, 0xF1, 0x61, 0xF1, 0x72};
    MtcReader r;
    std::vector<double> at;
    const std::vector<Timecode> got = Feed(r, bytes, &at);
    REQUIRE(got.size() == 1);
    CHECK(got[0] == Tc(1, 2, 3, 4, MtcRate::Fps25));
    CHECK(r.direction == 1);
    // The last piece is sent 1 3/4 frames after the frame the pieces name.
    CHECK(at[0] == Approx(3723.0 + 4 / 25.0 + 1.75 / 25.0));
    // Seven pieces are not a time.
    MtcReader partial;
    CHECK(Feed(partial, std::vector<uint8_t>(bytes.begin(), bytes.begin() + 14)).empty());
}

TEST_CASE("mtc: all four rates round trip through quarter frames and full frames, with their seconds") {
    struct Case { MtcRate rate; Timecode tc; std::vector<uint8_t> full; double seconds; };
    const Case cases[] = {
        {MtcRate::Fps24, Tc(0, 0, 1, 23, MtcRate::Fps24), {0xF0, 0x7F, 0x7F, 0x01, 0x01, 0x00, 0x00, 0x01, 0x17, 0xF7}, 1 + 23 / 24.0},
        {MtcRate::Fps25, Tc(10, 59, 59, 24, MtcRate::Fps25), {0xF0, 0x7F, 0x7F, 0x01, 0x01, 0x2A, 0x3B, 0x3B, 0x18, 0xF7},
         10 * 3600 + 59 * 60 + 59 + 24 / 25.0},
        // 29.97 drop-frame: 00:01:00;02 is the first label of minute 1 (;00 and ;01 are dropped):
        // frame 1800 of the count.
        {MtcRate::Fps2997Drop, Tc(0, 1, 0, 2, MtcRate::Fps2997Drop), {0xF0, 0x7F, 0x7F, 0x01, 0x01, 0x40, 0x01, 0x00, 0x02, 0xF7},
         1800 * 1001.0 / 30000.0},
        {MtcRate::Fps30, Tc(23, 0, 0, 29, MtcRate::Fps30), {0xF0, 0x7F, 0x7F, 0x01, 0x01, 0x77, 0x00, 0x00, 0x1D, 0xF7},
         23 * 3600 + 29 / 30.0},
    };
    for (const Case& c : cases) {
        INFO(FormatTimecode(c.tc));
        CHECK(MtcFullFrame(c.tc) == c.full);
        Timecode parsed;
        REQUIRE(ParseMtcFullFrame(c.full.data(), c.full.size(), &parsed));
        CHECK(parsed == c.tc);
        CHECK(TimecodeSeconds(c.tc) == Approx(c.seconds).epsilon(1e-12));
        CHECK(TimecodeAt(c.seconds + 0.1 / MtcFramesPerSecond(c.rate), c.rate) == c.tc);
        MtcReader r;
        const std::vector<Timecode> got = Feed(r, MtcQuarterFrames(c.tc));
        REQUIRE(got.size() == 1);
        CHECK(got[0] == c.tc);
    }
    CHECK(MtcFramesPerSecond(MtcRate::Fps2997Drop) == Approx(29.97).epsilon(1e-4));
    // 10 minutes of drop-frame are 17982 frames: 00:10:00;00 exists and is frame 17982.
    CHECK(TimecodeSeconds(Tc(0, 10, 0, 0, MtcRate::Fps2997Drop)) * 30000.0 / 1001.0 == Approx(17982.0));
    CHECK(TimecodeAt(17982 * 1001.0 / 30000.0 + 1e-4, MtcRate::Fps2997Drop) == Tc(0, 10, 0, 0, MtcRate::Fps2997Drop));
    CHECK(TimecodeAt(1799 * 1001.0 / 30000.0 + 1e-4, MtcRate::Fps2997Drop) == Tc(0, 0, 59, 29, MtcRate::Fps2997Drop));
}

TEST_CASE("mtc: bad full frames and stray quarter frames are refused, not misread") {
    Timecode tc;
    const std::vector<uint8_t> notMtc = {0xF0, 0x7E, 0x7F, 0x01, 0x01, 0x20, 0x00, 0x00, 0x00, 0xF7};   // non-realtime
    const std::vector<uint8_t> userBits = {0xF0, 0x7F, 0x7F, 0x01, 0x02, 0x20, 0x00, 0x00, 0x00, 0xF7};
    const std::vector<uint8_t> badMinute = {0xF0, 0x7F, 0x7F, 0x01, 0x01, 0x20, 0x3C, 0x00, 0x00, 0xF7};   // 60
    const std::vector<uint8_t> badFrame = {0xF0, 0x7F, 0x7F, 0x01, 0x01, 0x20, 0x00, 0x00, 0x19, 0xF7};    // 25 at 25 fps
    const std::vector<uint8_t> shortOne = {0xF0, 0x7F, 0x7F, 0x01, 0x01, 0x20, 0x00, 0xF7};
    for (const auto* b : {&notMtc, &userBits, &badMinute, &badFrame, &shortOne}) CHECK_FALSE(ParseMtcFullFrame(b->data(), b->size(), &tc));

    // Pieces 3..7 then 0..7: the first five are out of any sequence start; only the second run is a time.
    std::vector<uint8_t> bytes = MtcQuarterFrames(Tc(0, 0, 5, 0, MtcRate::Fps25));
    std::vector<uint8_t> stray(bytes.begin() + 6, bytes.end());
    stray.insert(stray.end(), bytes.begin(), bytes.end());
    MtcReader r;
    const std::vector<Timecode> got = Feed(r, stray);
    REQUIRE(got.size() == 1);
    CHECK(got[0] == Tc(0, 0, 5, 0, MtcRate::Fps25));
    // A piece lost in the middle (piece 4 dropped): no time from that run, counted.
    std::vector<uint8_t> lost = bytes;
    lost.erase(lost.begin() + 8, lost.begin() + 10);
    MtcReader r2;
    CHECK(Feed(r2, lost).empty());
    CHECK(r2.outOfSequence == 1);
}

TEST_CASE("mtc: a running master, forwards then backwards, gives consecutive times and the direction") {
    MtcReader r;
    std::vector<uint8_t> bytes;
    for (int f = 0; f < 10; f += 2) {   // 8 quarter frames per 2 frames
        const std::vector<uint8_t> q = MtcQuarterFrames(Tc(0, 0, 1, f, MtcRate::Fps30));
        bytes.insert(bytes.end(), q.begin(), q.end());
    }
    std::vector<Timecode> got = Feed(r, bytes);
    REQUIRE(got.size() == 5);
    for (int k = 0; k < 5; ++k) CHECK(got[k].frames == 2 * k);
    CHECK(r.direction == 1);
    // Backwards: pieces 7..0.
    bytes.clear();
    for (int f = 10; f > 0; f -= 2) {
        const std::vector<uint8_t> q = MtcQuarterFrames(Tc(0, 0, 1, f, MtcRate::Fps30), true);
        bytes.insert(bytes.end(), q.begin(), q.end());
    }
    got = Feed(r, bytes);
    REQUIRE(got.size() == 5);
    CHECK(got[0].frames == 10);
    CHECK(got[4].frames == 2);
    CHECK(r.direction == -1);
}

TEST_CASE("mtc: the show clock follows the master within a frame, seeks on a jump, holds on a locate, freewheels then stops on a dropout") {
    MtcSync s;
    CHECK(s.state == MtcSync::State::Waiting);
    const double fps = 25.0, frame = 1.0 / fps;
    // The master runs from 10 s; the local clock starts at 100 s. A time every 2 frames.
    double local = 100.0, master = 10.0;
    for (int k = 0; k < 50; ++k) {
        MtcOnQuarterFrame(s, local);
        MtcOnTimecode(s, master, MtcRate::Fps25, local, false, 1);
        for (int q = 0; q < 8; ++q) {   // between times: the clock runs on the local clock
            MtcTick(s, local + q * frame / 4);
            CHECK(std::abs(MtcShowTime(s, local + q * frame / 4) - (master + q * frame / 4)) < frame);
        }
        local += 2 * frame;
        master += 2 * frame;
    }
    CHECK(s.state == MtcSync::State::Locked);
    CHECK(s.seeks == 0);
    REQUIRE(!s.pending.empty());
    CHECK(s.pending.front().find("MTC locked at 00:00:10:00@25") == 0);
    s.pending.clear();

    // A jump: 1 minute on. The clock seeks and says so.
    master = 70.0;
    MtcOnTimecode(s, master, MtcRate::Fps25, local, false, 1);
    CHECK(MtcShowTime(s, local) == Approx(70.0));
    CHECK(s.seeks == 1);
    REQUIRE(s.pending.size() == 1);
    CHECK(s.pending[0].find("MTC jump to 00:01:10:00@25") == 0);
    s.pending.clear();

    // A stop: the master sends a full frame where it stopped; the clock holds there.
    MtcOnTimecode(s, 71.0, MtcRate::Fps25, local + 1.0, true);
    for (double t = 1.0; t < 4.0; t += 0.5) {
        MtcTick(s, local + t);
        CHECK(MtcShowTime(s, local + t) == Approx(71.0));
    }
    CHECK(s.state == MtcSync::State::Holding);
    s.pending.clear();

    // Running again, then a dropout: locked -> freewheel after 0.25 s (said once), still running
    // at speed 1 -> stopped 2 s later.
    local += 4.0;
    MtcOnQuarterFrame(s, local);
    MtcOnTimecode(s, 71.0, MtcRate::Fps25, local, false, 1);
    CHECK(s.state == MtcSync::State::Locked);
    MtcTick(s, local + 0.2);
    CHECK(s.state == MtcSync::State::Locked);
    MtcTick(s, local + 0.3);
    CHECK(s.state == MtcSync::State::Freewheel);
    MtcTick(s, local + 0.4);
    CHECK(MtcShowTime(s, local + 1.0) == Approx(72.0));
    int lost = 0;
    for (const std::string& line : s.pending) lost += line.find("freewheeling") != std::string::npos;
    CHECK(lost == 1);
    CHECK(MtcStatusLine(s, local + 1.0).find("master lost: freewheeling") != std::string::npos);
    MtcTick(s, local + 2.5);
    CHECK(s.state == MtcSync::State::Stopped);
    CHECK(MtcShowTime(s, local + 5.0) == Approx(73.5));
    // The master comes back: locked at its time, said.
    s.pending.clear();
    MtcOnQuarterFrame(s, local + 6.0);
    MtcOnTimecode(s, 80.0, MtcRate::Fps25, local + 6.0, false, 1);
    CHECK(s.state == MtcSync::State::Locked);
    CHECK(MtcShowTime(s, local + 6.5) == Approx(80.5));
    REQUIRE(!s.pending.empty());
    CHECK(s.pending.back().find("master back") != std::string::npos);
}

TEST_CASE("mtc: the MIDI decoder turns quarter frames and a full-frame SysEx into events, other SysEx stays ignored") {
    MidiDecoder d;
    std::vector<ControlEvent> ev;
    std::vector<uint8_t> bytes = MtcQuarterFrames(Tc(0, 0, 2, 10, MtcRate::Fps24));
    bytes.insert(bytes.begin() + 3, 0xF8);   // a clock byte in the middle of a quarter frame
    const std::vector<uint8_t> full = MtcFullFrame(Tc(1, 0, 0, 0, MtcRate::Fps30));
    bytes.insert(bytes.end(), full.begin(), full.end());
    const std::vector<uint8_t> other = {0xF0, 0x43, 0x10, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0xF7};   // same size, not MTC
    bytes.insert(bytes.end(), other.begin(), other.end());
    bytes.insert(bytes.end(), {0x90, 60, 100});
    DecodeMidiBytes(d, bytes.data(), bytes.size(), 1.5, &ev);
    REQUIRE(ev.size() == 8 + 1 + 1 + 1);
    MtcReader r;
    Timecode tc;
    int whole = 0;
    for (size_t i = 0; i < 9; ++i) {
        uint8_t data = 0;
        if (ev[i].midi[0] == 0xF8) continue;
        REQUIRE(MtcEventOf(ev[i], &data, &tc) == MtcEventKind::QuarterFrame);
        if (MtcQuarterFrame(r, data, &tc)) ++whole;
    }
    CHECK(whole == 1);
    CHECK(tc == Tc(0, 0, 2, 10, MtcRate::Fps24));
    uint8_t data = 0;
    REQUIRE(MtcEventOf(ev[9], &data, &tc) == MtcEventKind::FullFrame);
    CHECK(tc == Tc(1, 0, 0, 0, MtcRate::Fps30));
    CHECK(ev[10].midi[0] == 0x90);
    CHECK(MtcEventOf(ev[10], &data, &tc) == MtcEventKind::None);
    CHECK(d.ignored == 1);   // the other SysEx
    CHECK(d.stray == 0);
}
