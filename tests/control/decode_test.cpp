// Decoding and queue tests: running status, stray bytes, SysEx; OSC packets from bytes.
#include <lo/lo.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <functional>
#include <thread>

#include "test_util.h"

using namespace sdfvj;

namespace {
std::vector<ControlEvent> Decode(MidiDecoder& d, std::vector<uint8_t> bytes) {
    std::vector<ControlEvent> out;
    DecodeMidiBytes(d, bytes.data(), bytes.size(), 1.0, &out);
    return out;
}
}  // namespace

TEST_CASE("midi decode: running status, realtime bytes inside messages, stray data") {
    MidiDecoder d;
    // A MIDI clock pulse (0xF8) inside a running-status message is an event of its own (the
    // tempo follows it) and does not break the message around it; active sensing is ignored.
    auto ev = Decode(d, {0xB0, 1, 10, 2, 20, 0xF8, 3, 0xFE, 30});
    REQUIRE(ev.size() == 4);
    CHECK(ev[1].midi[0] == 0xB0);
    CHECK(ev[1].midi[1] == 2);
    CHECK(ev[1].midi[2] == 20);
    CHECK(ev[2].midiSize == 1);
    CHECK(ev[2].midi[0] == 0xF8);
    CHECK(ev[3].midi[1] == 3);
    CHECK(ev[3].midi[2] == 30);
    CHECK(d.ignored == 1);
    // Running status carries across calls (ALSA raw delivers it that way).
    ev = Decode(d, {4, 40});
    REQUIRE(ev.size() == 1);
    CHECK(ev[0].midi[1] == 4);
    // Program change: one data byte, running status too.
    ev = Decode(d, {0xC2, 5, 6});
    REQUIRE(ev.size() == 2);
    CHECK(ev[1].midiSize == 2);
    CHECK(ev[1].midi[1] == 6);
    // SysEx cancels running status; its data is skipped, data after it is stray.
    ev = Decode(d, {0xF0, 0x7E, 1, 2, 0xF7, 9, 9});
    CHECK(ev.empty());
    CHECK(d.stray == 2);
    MidiDecoder fresh;
    Decode(fresh, {1, 2, 3});
    CHECK(fresh.stray == 3);
    // System common (song position) skips its two data bytes.
    ev = Decode(fresh, {0xF2, 1, 2, 0x90, 60, 100});
    REQUIRE(ev.size() == 1);
    CHECK(fresh.stray == 3);
}

TEST_CASE("midi decode: clock, start, continue and stop become one-byte events that no mapping entry takes") {
    MidiDecoder d;
    auto ev = Decode(d, {0xFA, 0xF8, 0xF8, 0xFC, 0xFB, 0xFF, 0xF9});
    REQUIRE(ev.size() == 5);
    CHECK(ev[0].midi[0] == 0xFA);
    CHECK(ev[3].midi[0] == 0xFC);
    CHECK(ev[4].midi[0] == 0xFB);
    for (const ControlEvent& e : ev) CHECK(e.midiSize == 1);
    CHECK(d.ignored == 2);
    // The mapping ignores them: a mapping of every kind of source, parameters unchanged.
    Mapping m;
    REQUIRE(ParseMapping("[[map]]\ncc = 0\ntarget = \"a\"\n[[map]]\nprogram = \"any\"\naction = \"preset\"\n", "m.toml", &m).ok);
    ParamDecl a;
    a.name = "a";
    ParamState p = MakeParamState({a});
    MappingState ms;
    MappingActions acts;
    for (const ControlEvent& e : ev) ApplyEvent(m, ms, e, p, &acts);
    CHECK(p.target[0] == 0.0f);
    CHECK(acts.presetSelect.empty());
}

TEST_CASE("osc decode: packets from bytes, wrong types and garbage are counted") {
    std::vector<ControlEvent> out;
    OscDecodeCounts c;
    lo_message m = lo_message_new();
    lo_message_add_float(m, 0.25f);
    size_t len = 0;
    void* buf = lo_message_serialise(m, "/sdfvj/param/twist", nullptr, &len);
    DecodeOscPacket(static_cast<uint8_t*>(buf), len, 2.0, &out, &c);
    REQUIRE(out.size() == 1);
    CHECK(out[0].address == "/sdfvj/param/twist");
    CHECK(out[0].args[0].f == 0.25f);
    CHECK(out[0].time == 2.0);
    // Truncated: every prefix is either malformed or (by chance) still a valid message.
    for (size_t n = 0; n < len; ++n) DecodeOscPacket(static_cast<uint8_t*>(buf), n, 0.0, nullptr, &c);
    CHECK(c.malformed >= 1);
    free(buf);
    lo_message_free(m);

    m = lo_message_new();
    lo_message_add_string(m, "hello");
    buf = lo_message_serialise(m, "/sdfvj/param/twist", nullptr, &len);
    OscDecodeCounts c2;
    DecodeOscPacket(static_cast<uint8_t*>(buf), len, 0.0, &out, &c2);
    CHECK(c2.wrongType == 1);
    free(buf);
    lo_message_free(m);

    const uint8_t junk[] = {'#', 'b', 'u', 'n', 'd', 'l', 'e', 0, 0, 0, 0, 0, 0, 0, 0, 1, 0xff, 0xff, 0xff, 0xf0};
    OscDecodeCounts c3;
    DecodeOscPacket(junk, sizeof junk, 0.0, &out, &c3);
    CHECK(c3.malformed == 1);
}

TEST_CASE("midi queue: drains in order up to a time, drops and counts when full") {
    EventQueue q(4);
    for (int i = 0; i < 6; ++i) {
        ControlEvent e;
        e.time = i;
        q.Push(e);
    }
    CHECK(q.Dropped() == 2);
    auto a = q.DrainUntil(1.5);
    REQUIRE(a.size() == 2);
    CHECK(a[1].time == 1.0);
    CHECK(q.DrainUntil(10).size() == 2);
    // Many producers, one consumer: nothing lost below capacity.
    EventQueue big;
    std::vector<std::thread> producers;
    for (int t = 0; t < 4; ++t)
        producers.emplace_back([&] {
            for (int i = 0; i < 5000; ++i) big.Push(ControlEvent{});
        });
    size_t got = 0;
    while (got < 20000) got += big.DrainUntil(1.0).size();
    for (auto& p : producers) p.join();
    CHECK(got == 20000);
    CHECK(big.Dropped() == 0);
}

TEST_CASE("osc decode: arguments at 4-byte aligned addresses (as liblo hands them) decode without misaligned reads") {
    // liblo's argv points into the packet; an 8-byte lo_arg read there is undefined behaviour
    // (UBSan stopped `live` in the stage soak). The sanitizer pass runs this test.
    alignas(8) unsigned char buf[64] = {};
    unsigned char* at = buf + 4;   // 4-byte aligned, not 8
    const float f = 0.25f;
    const double d = 1e300;        // beyond float: an infinity, then rejected as not finite
    const int64_t h = 5000000000LL;
    std::vector<ControlEvent> out;
    ControlEvent e;
    std::string why;
    std::memcpy(at, &f, sizeof f);
    const void* argv[1] = {at};
    REQUIRE(DecodeOscMessage("/sdfvj/param/twist", "f", argv, 1, 0.0, &e, &why));
    CHECK(e.args[0].f == 0.25f);
    std::memcpy(at, &d, sizeof d);
    DecodeOscMessage("/x", "d", argv, 1, 0.0, &e, &why);
    REQUIRE(e.args.size() == 1);
    CHECK(std::isinf(e.args[0].f));
    std::memcpy(at, &h, sizeof h);
    REQUIRE(DecodeOscMessage("/x", "h", argv, 1, 0.0, &e, &why));
    CHECK(e.args[0].i == INT32_MAX);
}

namespace {

// /sdfvj/clock as a leader sends it, built by `add` on a liblo message, through the packet decoder.
struct ClockResult {
    OscDecodeCounts counts;
    std::vector<ControlEvent> events;
};
ClockResult DecodeClock(const std::function<void(lo_message)>& add) {
    ClockResult r;
    lo_message m = lo_message_new();
    add(m);
    size_t len = 0;
    void* buf = lo_message_serialise(m, "/sdfvj/clock", nullptr, &len);
    DecodeOscPacket(static_cast<uint8_t*>(buf), len, 3.0, &r.events, &r.counts);
    free(buf);
    lo_message_free(m);
    return r;
}

OscArg Int(int32_t v) {
    OscArg a;
    a.type = 'i';
    a.i = v;
    a.f = float(v);
    return a;
}
OscArg Str(const std::string& s) {
    OscArg a;
    a.type = 's';
    a.s = s;
    return a;
}
OscArg Flt(float f) {
    OscArg a;
    a.f = f;
    return a;
}

}  // namespace

TEST_CASE("osc decode: /sdfvj/clock carries a leader's show time, running flag and rendered values") {
    ClockResult r = DecodeClock([](lo_message m) {
        lo_message_add_int32(m, 12);
        lo_message_add_int32(m, 345678);
        lo_message_add_int32(m, 1);
        lo_message_add_string(m, "twist");
        lo_message_add_float(m, -1.25f);
        lo_message_add_string(m, "scale");
        lo_message_add_int32(m, 2);
    });
    REQUIRE(r.counts.ok == 1);
    REQUIRE(r.events.size() == 1);
    LeaderClock c;
    std::string why;
    REQUIRE(ParseLeaderClock(r.events[0].args, &c, &why));
    CHECK(c.seconds == Approx(12.345678).margin(1e-9));
    CHECK(c.running);
    REQUIRE(c.values.size() == 2);
    CHECK(c.values[0] == std::make_pair(std::string("twist"), -1.25f));
    CHECK(c.values[1] == std::make_pair(std::string("scale"), 2.0f));
    // Stopped, no values, the largest time; T/F and 64-bit ints are ints too.
    r = DecodeClock([](lo_message m) {
        lo_message_add_int64(m, kLeaderClockMaxSeconds);
        lo_message_add_int32(m, 999999);
        lo_message_add_false(m);
    });
    REQUIRE(r.events.size() == 1);
    REQUIRE(ParseLeaderClock(r.events[0].args, &c, &why));
    CHECK_FALSE(c.running);
    CHECK(c.values.empty());
    CHECK(c.seconds == Approx(kLeaderClockMaxSeconds + 0.999999).margin(1e-6));
    // The mapping leaves it to the show clock: nothing moves, nothing is rejected.
    ParamState p = MakeParamState(test::MidiSceneDecls());
    MappingState ms;
    MappingActions acts;
    ApplyEvent(Mapping{}, ms, r.events[0], p, &acts);
    CHECK(acts.messages.empty());
    CHECK(p.target == MakeParamState(test::MidiSceneDecls()).target);
}

TEST_CASE("osc decode: /sdfvj/clock with wrong types, NaN or out-of-range values is a counted bad message") {
    // Over the wire: each is counted as a wrong message and never queued.
    const std::vector<std::function<void(lo_message)>> bad = {
        [](lo_message m) { lo_message_add_float(m, 1.5f), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1); },
        [](lo_message m) { lo_message_add_double(m, 1.5), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1); },
        [](lo_message m) { lo_message_add_int32(m, 1), lo_message_add_int32(m, 0); },
        [](lo_message) {},
        [](lo_message m) { lo_message_add_string(m, "12"), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1); },
        [](lo_message m) { lo_message_add_int32(m, -1), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1); },
        [](lo_message m) { lo_message_add_int32(m, kLeaderClockMaxSeconds + 1), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1); },
        [](lo_message m) { lo_message_add_int64(m, int64_t(1) << 40), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1); },
        [](lo_message m) { lo_message_add_int32(m, 1), lo_message_add_int32(m, 1000000), lo_message_add_int32(m, 1); },
        [](lo_message m) { lo_message_add_int32(m, 1), lo_message_add_int32(m, -5), lo_message_add_int32(m, 1); },
        [](lo_message m) { lo_message_add_int32(m, 1), lo_message_add_int32(m, 0), lo_message_add_int32(m, 2); },
        [](lo_message m) {   // a value with no name
            lo_message_add_int32(m, 1), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1), lo_message_add_string(m, "twist");
        },
        [](lo_message m) {
            lo_message_add_int32(m, 1), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1);
            lo_message_add_float(m, 1.0f), lo_message_add_float(m, 1.0f);
        },
        [](lo_message m) {
            lo_message_add_int32(m, 1), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1);
            lo_message_add_string(m, "twist"), lo_message_add_string(m, "1.0");
        },
        [](lo_message m) {
            lo_message_add_int32(m, 1), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1);
            lo_message_add_string(m, "twist"), lo_message_add_float(m, std::nanf(""));
        },
        [](lo_message m) {
            lo_message_add_int32(m, 1), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1);
            lo_message_add_string(m, "twist"), lo_message_add_double(m, 1e300);
        },
        [](lo_message m) {
            lo_message_add_int32(m, 1), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1);
            lo_message_add_string(m, ""), lo_message_add_float(m, 1.0f);
        },
        [](lo_message m) {
            lo_message_add_int32(m, 1), lo_message_add_int32(m, 0), lo_message_add_int32(m, 1);
            for (int k = 0; k < 257; ++k) lo_message_add_string(m, "p"), lo_message_add_float(m, 0.0f);
        },
    };
    for (size_t k = 0; k < bad.size(); ++k) {
        INFO("bad message " << k);
        ClockResult r = DecodeClock(bad[k]);
        CHECK(r.counts.wrongType == 1);
        CHECK(r.counts.ok == 0);
        CHECK(r.events.empty());
    }
    // What is said: the address, what is wrong, what was expected.
    std::string why;
    LeaderClock c;
    CHECK_FALSE(ParseLeaderClock({Flt(1.5f), Int(0), Int(1)}, &c, &why));
    CHECK(why == "/sdfvj/clock: expected int SECONDS, int MICROSECONDS, int RUNNING (iii), then NAME VALUE pairs");
    CHECK_FALSE(ParseLeaderClock({Int(-1), Int(0), Int(1)}, &c, &why));
    CHECK(why == "/sdfvj/clock: seconds -1 out of range, expected 0..10000000");
    CHECK_FALSE(ParseLeaderClock({Int(1), Int(1000000), Int(1)}, &c, &why));
    CHECK(why == "/sdfvj/clock: microseconds 1000000 out of range, expected 0..999999");
    CHECK_FALSE(ParseLeaderClock({Int(1), Int(0), Int(7)}, &c, &why));
    CHECK(why == "/sdfvj/clock: running 7, expected 1 (running) or 0 (stopped)");
    CHECK_FALSE(ParseLeaderClock({Int(1), Int(0), Int(1), Str("twist"), Flt(INFINITY)}, &c, &why));
    CHECK(why == "/sdfvj/clock: twist: value is not finite");
    CHECK_FALSE(ParseLeaderClock({Int(1), Int(0), Int(1), Flt(2.0f), Flt(1.0f)}, &c, &why));
    CHECK(why == "/sdfvj/clock: argument 4 is not a parameter name, expected a string of 1..64 bytes");
    CHECK_FALSE(ParseLeaderClock({Int(1), Int(0), Int(1), Str("twist"), Str("x")}, &c, &why));
    CHECK(why == "/sdfvj/clock: twist: expected a float value");
}

TEST_CASE("osc decode: /sdfvj/effects takes one effect list, and the mapping asks for that whole set") {
    lo_message m = lo_message_new();
    lo_message_add_string(m, "ao,fog");
    size_t len = 0;
    void* buf = lo_message_serialise(m, "/sdfvj/effects", nullptr, &len);
    std::vector<ControlEvent> out;
    OscDecodeCounts c;
    DecodeOscPacket(static_cast<uint8_t*>(buf), len, 0.0, &out, &c);
    free(buf);
    lo_message_free(m);
    REQUIRE(out.size() == 1);
    ParamState p = MakeParamState(test::MidiSceneDecls());
    MappingState ms;
    MappingActions acts;
    ApplyEvent(Mapping{}, ms, out[0], p, &acts);
    // One toggle that clears first (live's ApplyActions parses it as an effect list).
    REQUIRE(acts.effectToggles.size() == 1);
    CHECK(acts.effectToggles[0] == std::make_pair(std::string("none,ao,fog"), true));
    m = lo_message_new();
    lo_message_add_int32(m, 1);
    buf = lo_message_serialise(m, "/sdfvj/effects", nullptr, &len);
    OscDecodeCounts c2;
    DecodeOscPacket(static_cast<uint8_t*>(buf), len, 0.0, nullptr, &c2);
    free(buf);
    lo_message_free(m);
    CHECK(c2.wrongType == 1);
}

TEST_CASE("osc decode: /sdfvj/env/NAME takes one number (1 fires, 0 releases), anything else is a counted bad message") {
    auto decode = [](const char* address, auto add) {
        lo_message m = lo_message_new();
        add(m);
        size_t len = 0;
        void* buf = lo_message_serialise(m, address, nullptr, &len);
        std::vector<ControlEvent> out;
        OscDecodeCounts c;
        DecodeOscPacket(static_cast<uint8_t*>(buf), len, 0.0, &out, &c);
        free(buf);
        lo_message_free(m);
        return std::make_pair(out, c.wrongType);
    };
    auto [fire, bad0] = decode("/sdfvj/env/hit", [](lo_message m) { lo_message_add_int32(m, 1); });
    REQUIRE(fire.size() == 1);
    CHECK(fire[0].address == "/sdfvj/env/hit");
    CHECK(fire[0].args[0].i == 1);
    CHECK(bad0 == 0);
    auto [none, bad1] = decode("/sdfvj/env/", [](lo_message m) { lo_message_add_int32(m, 1); });
    CHECK(none.empty());
    CHECK(bad1 == 1);
    auto [text, bad2] = decode("/sdfvj/env/hit", [](lo_message m) { lo_message_add_string(m, "on"); });
    CHECK(text.empty());
    CHECK(bad2 == 1);
    auto [empty, bad3] = decode("/sdfvj/env/hit", [](lo_message) {});
    CHECK(empty.empty());
    CHECK(bad3 == 1);
}
