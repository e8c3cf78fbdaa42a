// Round trips: Take -> SMF -> Take keeps every MIDI and OSC event, with times exact to the tick.
#include <catch2/catch.hpp>

#include "take/smf_bytes.h"
#include "take_test_util.h"

using namespace sdfvj;
using namespace take_test;

static Take SampleTake() {
    Take t;
    t.events = {
        Midi(0.0, {0xB0, 1, 0}),
        Midi(0.0, {0xB0, 2, 127}),              // same tick, order kept
        Midi(0.0123456, {0x90, 60, 100}),      // between ticks: rounds to the nearest
        Midi(0.25, {0xC3, 7}),                 // two-byte message
        Osc(0.2501, "/sdfvj/param/twist", {Arg('f', 0.75f)}),
        Midi(0.5, {0x80, 60, 0}),
        Osc(1.0, "/all/types", {Arg('i', 0, -42), Arg('f', -1.5f), Arg('s', 0, 0, "hello"), Arg('S', 0, 0, "sym"),
                                Arg('b', 0, 0, std::string("a\0b", 3)), Arg('h', 0, 123456), Arg('t', 0, 7),
                                Arg('d', 2.5f), Arg('c', 0, 'x'), Arg('r', 0, 0x11223344), Arg('m', 0, 0x00903C64),
                                Arg('T'), Arg('F'), Arg('N'), Arg('I')}),
        Osc(1.0, "/no/args", {}),
        Midi(1.5, {0xF8}),                     // MIDI clock: written as an F7 escape
        Midi(1.75, {0xF2, 0x10, 0x02}),        // song position
        Midi(2.0, {0xE0, 0x00, 0x40}),         // pitch bend
        Midi(3600.0 + 0.0005, {0xB0, 4, 64}),  // an hour in: still tick-exact
    };
    t.duration = 3601.0;
    return t;
}

static void RequireSameEvents(const Take& written, const Take& read) {
    REQUIRE(read.events.size() == written.events.size());
    for (size_t k = 0; k < written.events.size(); ++k) {
        const ControlEvent& a = written.events[k];
        const ControlEvent& b = read.events[k];
        INFO("event " << k);
        CHECK(b.time == QuantizeTakeTime(a.time));
        REQUIRE(b.source == a.source);
        if (a.source == EventSource::Midi) {
            REQUIRE(b.midiSize == a.midiSize);
            for (int i = 0; i < a.midiSize; ++i) CHECK(b.midi[i] == a.midi[i]);
            continue;
        }
        CHECK(b.address == a.address);
        REQUIRE(b.args.size() == a.args.size());
        for (size_t i = 0; i < a.args.size(); ++i) {
            INFO("arg " << i << " type " << a.args[i].type);
            CHECK(b.args[i].type == a.args[i].type);
            switch (a.args[i].type) {
                case 'f': case 'd': CHECK(b.args[i].f == a.args[i].f); break;
                case 's': case 'S': case 'b': CHECK(b.args[i].s == a.args[i].s); break;
                case 'i': case 'h': case 't': case 'c': case 'r': case 'm': CHECK(b.args[i].i == a.args[i].i); break;
                default: break;
            }
        }
    }
}

TEST_CASE("take: write-read round trip keeps MIDI and OSC events and their times", "[take]") {
    const Take written = SampleTake();
    TempFile file("roundtrip");
    std::string error;
    REQUIRE(WriteTake(file.path, written, &error));
    Take read;
    const TakeReadResult r = ReadTake(file.path, &read);
    REQUIRE(r.ok);
    CHECK(read.warnings.empty());
    RequireSameEvents(written, read);
    CHECK(read.duration == QuantizeTakeTime(3601.0));
}

TEST_CASE("take: times are exact to the 0.5 ms tick", "[take]") {
    CHECK(QuantizeTakeTime(0.0) == 0.0);
    CHECK(QuantizeTakeTime(0.00074) == 0.0005);
    CHECK(QuantizeTakeTime(0.00076) == 0.001);
    CHECK(QuantizeTakeTime(-3.0) == 0.0);
    Take t;
    for (int k = 0; k < 2000; ++k) t.events.push_back(Midi(k * 0.0005, {0xB0, 1, k % 128}));
    t.duration = 1.0;
    const std::vector<uint8_t> bytes = EncodeTake(t);
    Take back;
    REQUIRE(ParseTake(bytes.data(), bytes.size(), "ticks.mid", &back).ok);
    REQUIRE(back.events.size() == t.events.size());
    for (int k = 0; k < 2000; ++k) REQUIRE(back.events[k].time == QuantizeTakeTime(k * 0.0005));
}

TEST_CASE("take: recorder round trip with a time origin and an end time", "[take]") {
    const Take written = SampleTake();
    TempFile file("recorder");
    TakeRecorder rec;
    TakeRecorderDesc desc;
    desc.timeOrigin = 100.0;  // the session clock read 100 s when recording started
    std::string error;
    REQUIRE(rec.Open(file.path, desc, &error));
    for (const ControlEvent& e : written.events) {
        ControlEvent shifted = e;
        shifted.time += 100.0;
        rec.Record(shifted);
        if (e.time == 1.0) rec.Flush();  // a mid-take flush must not disturb anything
    }
    ControlEvent empty;  // no MIDI bytes: dropped, counted
    rec.Record(empty);
    rec.Close(100.0 + 3601.0);
    CHECK(rec.Recorded() == written.events.size());
    CHECK(rec.Dropped() == 1);
    CHECK(rec.Error().empty());

    Take read;
    const TakeReadResult r = ReadTake(file.path, &read);
    REQUIRE(r.ok);
    CHECK(read.warnings.empty());
    // Times relative to the origin; the shift by 100 s rounds differently by at most one tick.
    REQUIRE(read.events.size() == written.events.size());
    for (size_t k = 0; k < written.events.size(); ++k)
        CHECK(std::abs(read.events[k].time - written.events[k].time) <= 0.5 * kTakeSecondsPerTick + 1e-9);
    Take unshifted = written;
    for (size_t k = 0; k < unshifted.events.size(); ++k) unshifted.events[k].time = read.events[k].time;
    RequireSameEvents(unshifted, read);
    CHECK(read.duration == Approx(3601.0).margin(0.001));
}

TEST_CASE("take: recorder writes events out of order at the previous tick", "[take]") {
    TempFile file("order");
    TakeRecorder rec;
    std::string error;
    REQUIRE(rec.Open(file.path, &error));
    rec.Record(Midi(1.0, {0xB0, 1, 1}));
    rec.Record(Midi(0.5, {0xB0, 1, 2}));  // late event from a second input thread
    rec.Record(Midi(2.0, {0xB0, 1, 3}));
    rec.Close();
    Take read;
    REQUIRE(ReadTake(file.path, &read).ok);
    REQUIRE(read.events.size() == 3);
    CHECK(read.events[0].time == 1.0);
    CHECK(read.events[1].time == 1.0);
    CHECK(read.events[2].time == 2.0);
    CHECK(read.duration == 2.0);
}

TEST_CASE("take: recorder reports an unwritable path as a value", "[take]") {
    TakeRecorder rec;
    std::string error;
    CHECK_FALSE(rec.Open("/nonexistent-dir/take.mid", &error));
    CHECK(error.find("/nonexistent-dir/take.mid") != std::string::npos);
    CHECK_FALSE(rec.IsOpen());
    rec.Record(Midi(0, {0x90, 1, 1}));  // harmless when closed
    CHECK(rec.Dropped() == 1);
}

TEST_CASE("take: ReplayCursor yields every event once, in order", "[take]") {
    Take t;
    for (int k = 0; k < 100; ++k) t.events.push_back(Midi(k / 60.0 * 0.75, {0xB0, 1, k}));  // some on frame edges
    t.events.push_back(Midi(t.events.back().time, {0xB0, 2, 0}));                          // same time as the previous
    t.duration = 2.0;
    ReplayCursor cursor(t);
    CHECK(cursor.NextTime() == 0.0);
    std::vector<ControlEvent> seen;
    for (int frame = 0; !cursor.Done(); ++frame) {
        const double frameEnd = (frame + 1) / 60.0;
        for (const ControlEvent& e : cursor.Until(frameEnd)) {
            CHECK(e.time < frameEnd);
            CHECK(e.time >= frame / 60.0);  // not handed out a frame late
            seen.push_back(e);
        }
        CHECK(cursor.Until(frameEnd).empty());  // asking again gives nothing new
        REQUIRE(frame < 1000);
    }
    REQUIRE(seen.size() == t.events.size());
    for (size_t k = 0; k < seen.size(); ++k) {
        CHECK(seen[k].time == t.events[k].time);
        CHECK(seen[k].midi[1] == t.events[k].midi[1]);
        CHECK(seen[k].midi[2] == t.events[k].midi[2]);
    }
    CHECK(cursor.NextTime() == 2.0);
    CHECK(cursor.Until(1e9).empty());
    cursor.Rewind();
    std::vector<ControlEvent> all;
    CHECK(cursor.Until(1e9, &all) == t.events.size());
    CHECK(cursor.Done());
}

TEST_CASE("take: the demo take drives knobs 1-4 on channel 1 for 8 seconds", "[take]") {
    Take demo;
    const TakeReadResult r = ReadTake(std::string(SDFVJ_SOURCE_ROOT) + "/presets/demo_take.mid", &demo);
    REQUIRE(r.ok);
    CHECK(demo.warnings.empty());
    CHECK(demo.duration == 8.0);
    int ccs[5] = {0, 0, 0, 0, 0};
    int notes = 0;
    for (const ControlEvent& e : demo.events) {
        REQUIRE(e.source == EventSource::Midi);
        if (e.midi[0] == 0xB0 && e.midi[1] >= 1 && e.midi[1] <= 4) ++ccs[e.midi[1]];
        if (e.midi[0] == 0x90) ++notes;
    }
    for (int k = 1; k <= 4; ++k) CHECK(ccs[k] > 20);
    CHECK(notes == 4);
}
