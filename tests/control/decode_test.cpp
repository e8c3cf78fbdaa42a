// Decoding and queue tests: running status, stray bytes, SysEx; OSC packets from bytes.
#include <lo/lo.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
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
