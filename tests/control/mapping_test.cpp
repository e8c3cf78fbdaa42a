// Mapping unit tests: curves, takeover, relative encoders, 14-bit pairs, NRPN, pads, TOML errors.
// ApplyEvent is pure, so these need no device.
#include <catch2/catch.hpp>

#include "test_util.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

ControlEvent Midi(uint8_t s, uint8_t a, uint8_t b = 0, uint8_t size = 3) {
    ControlEvent e;
    e.source = EventSource::Midi;
    e.midi[0] = s;
    e.midi[1] = a;
    e.midi[2] = b;
    e.midiSize = size;
    return e;
}
ControlEvent Cc(int cc, int v, int ch = 1) { return Midi(uint8_t(0xB0 | (ch - 1)), uint8_t(cc), uint8_t(v)); }
ControlEvent NoteOn(int n, int v = 100) { return Midi(0x90, uint8_t(n), uint8_t(v)); }
ControlEvent NoteOff(int n) { return Midi(0x80, uint8_t(n), 0); }

Mapping Parse(const std::string& toml) {
    Mapping m;
    LoadResult r = ParseMapping(toml, "test.toml", &m);
    INFO(r.error);
    REQUIRE(r.ok);
    return m;
}

struct Rig {
    Mapping m;
    MappingState ms;
    ParamState p = MakeParamState(MidiSceneDecls());
    MappingActions acts;
    explicit Rig(const std::string& toml) : m(Parse(toml)) {}
    Rig& Send(const ControlEvent& e) {
        ApplyEvent(m, ms, e, p, &acts);
        return *this;
    }
    float operator[](const char* name) const { return Param(p, name); }
};

}  // namespace

TEST_CASE("midi mapping: every curve is monotonic, hits its ends and inverts") {
    for (Curve c : {Curve::Linear, Curve::Exponential, Curve::Logarithmic, Curve::S}) {
        CHECK(ApplyCurve(c, 0.0f, -1.0f) == Approx(0.0f).margin(1e-6));
        CHECK(ApplyCurve(c, 1.0f, -1.0f) == Approx(1.0f).margin(1e-6));
        float prev = -1.0f;
        for (int i = 0; i <= 100; ++i) {
            float x = i / 100.0f, y = ApplyCurve(c, x, -1.0f);
            CHECK(y >= prev);
            prev = y;
            CHECK(InverseCurve(c, y, -1.0f) == Approx(x).margin(1e-4));
        }
    }
    CHECK(ApplyCurve(Curve::Linear, 0.3f, -1) == Approx(0.3f));
    CHECK(ApplyCurve(Curve::Exponential, 0.5f, -1) < 0.3f);     // slow start
    CHECK(ApplyCurve(Curve::Logarithmic, 0.5f, -1) > 0.7f);     // fast start
    CHECK(ApplyCurve(Curve::S, 0.5f, -1) == Approx(0.5f));
    CHECK(ApplyCurve(Curve::S, 0.25f, -1) < 0.25f);
    CHECK(ApplyCurve(Curve::S, 0.75f, -1) > 0.75f);
    CHECK(ApplyCurve(Curve::Exponential, 0.5f, 6.0f) < ApplyCurve(Curve::Exponential, 0.5f, 2.0f));
}

TEST_CASE("midi mapping: curves, ranges and invert through ApplyEvent") {
    Rig r(R"(
[[map]]
cc = 1
target = "scale"
[[map]]
cc = 2
target = "twist"
range = [0.0, 2.0]
curve = "exponential"
[[map]]
cc = 3
target = "displacement"
invert = true
curve = "logarithmic"
[[map]]
cc = 4
target = "smoothness"
curve = "s"
)");
    r.Send(Cc(1, 0));
    CHECK(r["scale"] == Approx(0.5f));
    r.Send(Cc(1, 127));
    CHECK(r["scale"] == Approx(2.0f));
    r.Send(Cc(2, 127));
    CHECK(r["twist"] == Approx(2.0f));
    r.Send(Cc(2, 64));
    CHECK(r["twist"] == Approx(2.0f * ApplyCurve(Curve::Exponential, 64 / 127.0f, -1)));
    r.Send(Cc(3, 127));
    CHECK(r["displacement"] == Approx(0.0f).margin(1e-6));
    r.Send(Cc(3, 0));
    CHECK(r["displacement"] == Approx(1.0f));
    r.Send(Cc(3, 32));
    CHECK(r["displacement"] == Approx(ApplyCurve(Curve::Logarithmic, 1.0f - 32 / 127.0f, -1)));
    r.Send(Cc(4, 32));
    CHECK(r["smoothness"] == Approx(0.5f * ApplyCurve(Curve::S, 32 / 127.0f, -1)));
    CHECK(r.p.clamped == 0);
}

TEST_CASE("midi mapping: channel filter and any channel") {
    Rig r(R"(
[profile]
channel = 10
[[map]]
cc = 1
target = "scale"
[[map]]
cc = 2
channel = "any"
target = "displacement"
)");
    r.Send(Cc(1, 127, 1));
    CHECK(r["scale"] == Approx(1.0f));  // channel 1 is not channel 10
    r.Send(Cc(1, 127, 10));
    CHECK(r["scale"] == Approx(2.0f));
    r.Send(Cc(2, 127, 7));
    CHECK(r["displacement"] == Approx(1.0f));
}

TEST_CASE("midi mapping: takeover none jumps") {
    Rig r("[[map]]\ncc = 1\ntarget = \"displacement\"\ntakeover = \"none\"\n");
    r.Send(Cc(1, 100));
    CHECK(r["displacement"] == Approx(100 / 127.0f));
    SetParamByName(r.p, "displacement", 0.1f, nullptr);  // e.g. a preset
    r.Send(Cc(1, 101));
    CHECK(r["displacement"] == Approx(101 / 127.0f));
}

TEST_CASE("midi mapping: takeover pickup waits until the control reaches the value") {
    Rig r("[[map]]\ncc = 1\ntarget = \"displacement\"\ntakeover = \"pickup\"\n");
    // Parameter at 0 (default); the knob starts at 100: ignored.
    r.Send(Cc(1, 100));
    CHECK(r["displacement"] == 0.0f);
    r.Send(Cc(1, 50));
    CHECK(r["displacement"] == 0.0f);
    r.Send(Cc(1, 1));  // within tolerance: picked up
    CHECK(r["displacement"] == Approx(1 / 127.0f));
    r.Send(Cc(1, 90));
    CHECK(r["displacement"] == Approx(90 / 127.0f));
    // A preset moves the parameter to 0.3 (x = 38.1): the knob at 90 no longer owns it.
    SetParamByName(r.p, "displacement", 0.3f, nullptr);
    r.Send(Cc(1, 80));
    CHECK(r["displacement"] == Approx(0.3f));
    r.Send(Cc(1, 30));  // crossed 38.1 on the way down: engaged
    CHECK(r["displacement"] == Approx(30 / 127.0f));
    r.Send(Cc(1, 31));
    CHECK(r["displacement"] == Approx(31 / 127.0f));
}

TEST_CASE("midi mapping: takeover scale converges so both reach the end together") {
    Rig r("[[map]]\ncc = 1\ntarget = \"displacement\"\ntakeover = \"scale\"\n");
    r.Send(Cc(1, 64));  // first sight of the knob: position known, value untouched
    CHECK(r["displacement"] == 0.0f);
    SetParamByName(r.p, "displacement", 0.2f, nullptr);
    r.Send(Cc(1, 64));
    CHECK(r["displacement"] == Approx(0.2f));
    r.Send(Cc(1, 96));  // moved 1/2 of the way to the top: parameter moves half of its way too
    float x0 = 64 / 127.0f, x1 = 96 / 127.0f;
    float expect = 0.2f + (x1 - x0) * (1.0f - 0.2f) / (1.0f - x0);
    CHECK(r["displacement"] == Approx(expect));
    r.Send(Cc(1, 127));
    CHECK(r["displacement"] == Approx(1.0f));
    r.Send(Cc(1, 100));  // engaged now: direct
    CHECK(r["displacement"] == Approx(100 / 127.0f));
    // Downwards scaling: the knob is at 100, the parameter at 0.2, below it.
    SetParamByName(r.p, "displacement", 0.2f, nullptr);
    r.Send(Cc(1, 50));
    float xa = 100 / 127.0f, xb = 50 / 127.0f;
    CHECK(r["displacement"] == Approx(0.2f - (xa - xb) * 0.2f / xa));
    r.Send(Cc(1, 0));
    CHECK(r["displacement"] == Approx(0.0f).margin(1e-6));
    // Crossing the parameter's position engages directly.
    SetParamByName(r.p, "displacement", 0.5f, nullptr);
    r.Send(Cc(1, 127));
    CHECK(r["displacement"] == Approx(1.0f));
}

TEST_CASE("midi mapping: relative encoder modes decode ticks") {
    using E = EncoderMode;
    CHECK(DecodeRelative(E::SignedBit, 0x01) == 1);
    CHECK(DecodeRelative(E::SignedBit, 0x41) == -1);
    CHECK(DecodeRelative(E::SignedBit, 0x05) == 5);
    CHECK(DecodeRelative(E::SignedBit, 0x45) == -5);
    CHECK(DecodeRelative(E::SignedBit2, 0x41) == 1);
    CHECK(DecodeRelative(E::SignedBit2, 0x01) == -1);
    CHECK(DecodeRelative(E::BinaryOffset, 65) == 1);
    CHECK(DecodeRelative(E::BinaryOffset, 63) == -1);
    CHECK(DecodeRelative(E::BinaryOffset, 64) == 0);
    CHECK(DecodeRelative(E::TwosComplement, 1) == 1);
    CHECK(DecodeRelative(E::TwosComplement, 127) == -1);
    CHECK(DecodeRelative(E::TwosComplement, 0x7D) == -3);
    CHECK(DecodeRelative(E::Absolute, 5) == 0);
}

TEST_CASE("midi mapping: relative encoders step from the current value and clamp at the ends") {
    for (auto [mode, up, down] : {std::tuple{"signed_bit", 0x02, 0x41}, std::tuple{"signed_bit2", 0x42, 0x01},
                                  std::tuple{"binary_offset", 66, 63}, std::tuple{"twos_complement", 2, 127}}) {
        INFO(mode);
        Rig r(std::string("[[map]]\ncc = 16\ntarget = \"smoothness\"\nstep = 0.1\nencoder = \"") + mode + "\"\n");
        // smoothness default 0.1 of [0, 0.5] -> position 0.2
        r.Send(Cc(16, up));  // +2 ticks -> 0.4 -> 0.2
        CHECK(r["smoothness"] == Approx(0.2f));
        r.Send(Cc(16, down));  // -1 tick -> 0.3 -> 0.15
        CHECK(r["smoothness"] == Approx(0.15f));
        for (int i = 0; i < 20; ++i) r.Send(Cc(16, up));
        CHECK(r["smoothness"] == Approx(0.5f));
        // Someone else moves it: the encoder continues from there.
        SetParamByName(r.p, "smoothness", 0.25f, nullptr);
        r.Send(Cc(16, down));
        CHECK(r["smoothness"] == Approx(0.2f));
        CHECK(r.p.clamped == 0);
    }
}

TEST_CASE("midi mapping: 14-bit CC pairs MSB n with LSB n+32") {
    Rig r("[[map]]\ncc14 = 7\ntarget = \"twist\"\n[[map]]\ncc = 8\nhires = true\ntarget = \"displacement\"\n");
    r.Send(Cc(39, 100));  // LSB before any MSB: ignored
    CHECK(r["twist"] == 0.0f);
    r.Send(Cc(7, 127));
    CHECK(r["twist"] == Approx(-3.0f + 6.0f * (127 * 128) / 16383.0f));
    r.Send(Cc(39, 127));
    CHECK(r["twist"] == Approx(3.0f));
    r.Send(Cc(7, 64)).Send(Cc(39, 0));
    CHECK(r["twist"] == Approx(-3.0f + 6.0f * 8192 / 16383.0f));
    r.Send(Cc(7, 0)).Send(Cc(39, 1));
    CHECK(r["twist"] == Approx(-3.0f + 6.0f / 16383.0f));
    r.Send(Cc(8, 0x20)).Send(Cc(40, 0x10));
    CHECK(r["displacement"] == Approx((0x20 * 128 + 0x10) / 16383.0f));
    // Resolution finer than 7 bits.
    float a = r["displacement"];
    r.Send(Cc(40, 0x11));
    CHECK(r["displacement"] - a == Approx(1.0f / 16383.0f).epsilon(0.01));
}

TEST_CASE("midi mapping: NRPN 14-bit and 7-bit values, RPN does not leak") {
    Rig r("[[map]]\nnrpn = 300\ntarget = \"displacement\"\n[[map]]\nnrpn = 5\nhires = false\ntarget = \"scale\"\n");
    r.Send(Cc(99, 2)).Send(Cc(98, 44)).Send(Cc(6, 100)).Send(Cc(38, 5));
    CHECK(r["displacement"] == Approx((100 * 128 + 5) / 16383.0f));
    r.Send(Cc(99, 0)).Send(Cc(98, 5)).Send(Cc(6, 127)).Send(Cc(38, 0));
    CHECK(r["scale"] == Approx(2.0f));
    // RPN 0 (pitch-bend range) data entry must not reach NRPN 5.
    r.Send(Cc(101, 0)).Send(Cc(100, 0)).Send(Cc(6, 0));
    CHECK(r["scale"] == Approx(2.0f));
}

TEST_CASE("midi mapping: pitch bend and program change") {
    Rig r("[[map]]\npitchbend = true\ntarget = \"twist\"\n[[map]]\nprogram = \"any\"\n[[map]]\nprogram = 3\npreset = \"third\"\n");
    r.Send(Midi(0xE0, 0x7F, 0x7F));
    CHECK(r["twist"] == Approx(3.0f));
    r.Send(Midi(0xE0, 0x00, 0x40));
    CHECK(r["twist"] == Approx(-3.0f + 6.0f * 8192 / 16383.0f));
    r.Send(Midi(0xC0, 7, 0, 2));
    REQUIRE(r.acts.presetSelect.size() == 1);
    CHECK(r.acts.presetSelect[0] == "7");
    r.Send(Midi(0xC0, 3, 0, 2));
    CHECK(r.acts.presetSelect.back() == "third");
}

TEST_CASE("midi mapping: pads trigger, toggle, preset, effect, tap tempo") {
    Rig r(R"(
[[pad]]
note = 36
action = "trigger"
target = "displacement"
[[pad]]
note = 37
action = "toggle"
target = "flag"
[[pad]]
note = 38
action = "preset"
preset = "intro"
[[pad]]
note = 39
action = "effect"
effect = "shadows"
[[pad]]
cc = 20
action = "tap_tempo"
)");
    r.Send(NoteOn(36));
    CHECK(r["displacement"] == 1.0f);
    CHECK(r.acts.triggers == std::vector<std::string>{"displacement"});
    r.Send(NoteOff(36));
    CHECK(r["displacement"] == 0.0f);
    r.Send(NoteOn(37)).Send(NoteOff(37));
    CHECK(r["flag"] == 1.0f);
    r.Send(NoteOn(37)).Send(Midi(0x90, 37, 0));  // note-on velocity 0 is a note-off
    CHECK(r["flag"] == 0.0f);
    r.Send(NoteOn(38)).Send(NoteOff(38));
    CHECK(r.acts.presetSelect == std::vector<std::string>{"intro"});
    r.Send(NoteOn(39)).Send(NoteOff(39)).Send(NoteOn(39));
    REQUIRE(r.acts.effectToggles.size() == 2);
    CHECK(r.acts.effectToggles[0] == std::pair<std::string, bool>{"shadows", true});
    CHECK(r.acts.effectToggles[1] == std::pair<std::string, bool>{"shadows", false});
    CHECK_FALSE(r.acts.tapTempo);
    r.Send(Cc(20, 127));
    CHECK(r.acts.tapTempo);
}

TEST_CASE("midi mapping: smoothing time constant is per entry and deterministic") {
    Rig r("[[map]]\ncc = 1\ntarget = \"displacement\"\nsmoothing = 0.1\n");
    r.Send(Cc(1, 127));
    CHECK(r.p.smoothingTau[FindParam(r.p, "displacement")] == Approx(0.1f));
    ParamState a = r.p, b = r.p;
    for (int i = 0; i < 6; ++i) StepSmoothing(a, 1.0 / 60.0);
    for (int i = 0; i < 6; ++i) StepSmoothing(b, 1.0 / 60.0);
    int i = FindParam(a, "displacement");
    CHECK(a.value[i] == b.value[i]);
    CHECK(a.value[i] == Approx(1.0 - std::exp(-0.1 / 0.1)).epsilon(1e-4));
    for (int k = 0; k < 600; ++k) StepSmoothing(a, 1.0 / 60.0);
    CHECK(a.value[i] == 1.0f);  // settles exactly
}

TEST_CASE("midi params: out-of-range values are clamped and reported") {
    ParamState p = MakeParamState(MidiSceneDecls());
    std::string err;
    CHECK_FALSE(SetParamByName(p, "twist", 10.0f, &err));
    CHECK(Param(p, "twist") == 3.0f);
    CHECK(err.find("clamped") != std::string::npos);
    CHECK(p.clamped == 1);
    CHECK_FALSE(SetParamByName(p, "nope", 1.0f, &err));
    CHECK(err.find("scale, twist, displacement, smoothness") != std::string::npos);
    CHECK_FALSE(SetParamByName(p, "scale", NAN, &err));
    CHECK(Param(p, "scale") == 1.0f);
    CHECK(SetParamByName(p, "scale", 1.5f, &err));
    // A mapping whose output range leaves the declared range is clamped too.
    Rig r("[[map]]\ncc = 1\ntarget = \"scale\"\nrange = [0.0, 10.0]\n");
    r.Send(Cc(1, 127));
    CHECK(r["scale"] == 2.0f);
    CHECK(r.p.clamped == 1);
    REQUIRE(r.acts.messages.size() == 1);
    CHECK(r.acts.messages[0].find("scale: 10 is outside [0.5, 2]") != std::string::npos);
}

TEST_CASE("midi mapping: TOML errors carry file:line:col and what was expected") {
    Mapping m;
    m.name = "untouched";
    auto err = [&](const std::string& text) {
        LoadResult r = ParseMapping(text, "bad.toml", &m);
        CHECK_FALSE(r.ok);
        return r.error;
    };
    CHECK(err("[[map]]\ncc = 1\ntarget = \"scale\"\ncurve = \"cubic\"\n") ==
          "bad.toml:4:9: bad value for 'curve', expected one of: linear, exponential, logarithmic, s");
    CHECK(err("[[map]]\ncc = 200\ntarget = \"scale\"\n") ==
          "bad.toml:2:6: bad value for 'cc', expected an integer 0..127");
    CHECK(err("[[map]]\ncc = 1\ntarget = \"scale\"\ncurev = \"s\"\n").rfind("bad.toml:4:9: unknown key 'curev'", 0) == 0);
    CHECK(err("[[map]]\ntarget = \"scale\"\n").rfind("bad.toml:1:1: entry has no source", 0) == 0);
    CHECK(err("[[map]]\ncc = 40\nhires = true\ntarget = \"x\"\n").rfind("bad.toml:3:9: 14-bit CC pairs", 0) == 0);
    CHECK(err("[[map]]\ncc = 1\ntarget = \"scale\"\nchannel = 17\n").rfind("bad.toml:4:11: bad value for 'channel'", 0) == 0);
    std::string syntax = err("[[map]]\ncc = = 1\n");
    CHECK(syntax.rfind("bad.toml:2:", 0) == 0);
    CHECK(syntax.find("expected valid TOML") != std::string::npos);
    CHECK(m.name == "untouched");  // a failed load keeps the last good mapping
    LoadResult missing = LoadMapping("/nonexistent/x.toml", &m);
    CHECK(missing.error.rfind("/nonexistent/x.toml:1:1: cannot open", 0) == 0);
}

TEST_CASE("midi mapping: unknown parameter names list the valid ones") {
    Mapping m = Parse("[[map]]\ncc = 1\ntarget = \"scale\"\n\n[[map]]\ncc = 2\ntarget = \"twsit\"\n");
    std::string err;
    CHECK_FALSE(ValidateMapping(m, MidiSceneDecls(), &err));
    CHECK(err == "test.toml:5:1: unknown parameter 'twsit', expected one of: scale, twist, displacement, smoothness, flag");
    // And at run time it is a counted rejection, not a crash.
    MappingState ms;
    ParamState p = MakeParamState(MidiSceneDecls());
    ApplyEvent(m, ms, Cc(2, 5), p, nullptr);
    CHECK(ms.rejected == 1);
}

TEST_CASE("midi mapping: shipped profiles load and map the midi scene to the first four knobs") {
    struct Profile { const char* file; int knobs[4]; };
    // First four knobs: LPD8 K1-K4 = CC 1-4 (factory program 1), nanoKONTROL2 knobs 1-4 = CC 16-19,
    // generic = CC 20-23 (an undefined-CC block most generic controllers default to or can be set to).
    for (Profile pr : {Profile{"akai_lpd8.toml", {1, 2, 3, 4}}, Profile{"korg_nanokontrol2.toml", {16, 17, 18, 19}},
                       Profile{"generic_8knob.toml", {20, 21, 22, 23}}}) {
        INFO(pr.file);
        Mapping m;
        LoadResult r = LoadMapping(std::string(SDFVJ_MAPPINGS_DIR) + "/" + pr.file, &m);
        INFO(r.error);
        REQUIRE(r.ok);
        std::vector<ParamDecl> decls = MidiSceneDecls();
        decls.pop_back();
        std::string err;
        // Pads may target other things; only the knob targets are checked here.
        const char* names[4] = {"scale", "twist", "displacement", "smoothness"};
        for (int k = 0; k < 4; ++k) {
            bool found = false;
            for (const MappingEntry& en : m.entries)
                if (en.kind == SourceKind::Cc && en.number == pr.knobs[k] &&
                    (en.target == names[k] || en.targetIndex == k + 1) && en.action == PadAction::None)
                    found = true;
            CHECK(found);
        }
        MappingState ms;
        ParamState p = MakeParamState(decls);
        for (int k = 0; k < 4; ++k) {
            for (int ch = 1; ch <= 16; ++ch) ApplyEvent(m, ms, Cc(pr.knobs[k], 127, ch), p, nullptr);
            CHECK(p.target[k] == Approx(decls[k].maxValue));
        }
        CHECK(ms.rejected == 0);
    }
}

TEST_CASE("midi mapping: positional targets drive any scene's Nth input") {
    Mapping m;
    REQUIRE(ParseMapping("[[map]]\ncc = 1\ntarget = 1\n[[map]]\ncc = 2\ntarget = 3\n[[map]]\ncc = 3\ntarget = 9\n",
                         "pos.toml", &m).ok);
    REQUIRE(m.entries.size() == 3);
    CHECK(m.entries[0].targetIndex == 1);
    auto decl = [](const std::string& n, float lo, float hi) { ParamDecl d; d.name = n; d.minValue = lo; d.maxValue = hi; return d; };
    for (const auto& decls : {std::vector<ParamDecl>{decl("twist", -3, 3), decl("scale", 0, 2), decl("glow", 0, 1)},
                              std::vector<ParamDecl>{decl("power", 2, 12), decl("x", 0, 1), decl("bailout", 1, 4)}}) {
        std::string problems;
        CHECK(ValidateMapping(m, decls, &problems));
        ParamState p = MakeParamState(decls);
        MappingState ms;
        MappingActions acts;
        ApplyEvent(m, ms, Midi(0xB0, 1, 127), p, &acts);
        ApplyEvent(m, ms, Midi(0xB0, 2, 0), p, &acts);
        ApplyEvent(m, ms, Midi(0xB0, 3, 64), p, &acts);   // a 9th input the scene lacks: nothing
        CHECK(p.target[0] == Approx(decls[0].maxValue));
        CHECK(p.target[2] == Approx(decls[2].minValue));
        CHECK(acts.messages.empty());
        CHECK(ms.rejected == 0);
    }
    CHECK_FALSE(ParseMapping("[[map]]\ncc = 1\ntarget = 0\n", "pos.toml", &m).ok);
}

TEST_CASE("midi mapping: preset pads pick from the profile's list, not from the folder's order") {
    Mapping m;
    REQUIRE(ParseMapping("[profile]\npresets = [\"walker\", \"demo\"]\n[[pad]]\nnote = 36\naction = \"preset\"\npreset = \"1\"\n"
                         "[[pad]]\nnote = 37\naction = \"preset\"\npreset = \"5\"\n[[pad]]\nnote = 38\naction = \"preset\"\npreset = \"bulb\"\n",
                         "list.toml", &m).ok);
    CHECK(m.presets == std::vector<std::string>{"walker", "demo"});
    ParamState p = MakeParamState({});
    MappingState ms;
    MappingActions acts;
    ApplyEvent(m, ms, Midi(0x90, 36, 100), p, &acts);
    ApplyEvent(m, ms, Midi(0x90, 37, 100), p, &acts);   // slot 5 of 2: rejected with a line
    ApplyEvent(m, ms, Midi(0x90, 38, 100), p, &acts);
    CHECK(acts.presetSelect == std::vector<std::string>{"demo", "bulb"});
    REQUIRE(acts.messages.size() == 1);
    CHECK(acts.messages[0].find("preset slot 5 is past the profile's 2 presets") != std::string::npos);
    Mapping bad;
    LoadResult r = ParseMapping("[profile]\npresets = [\"a/b\"]\n", "bad.toml", &bad);
    CHECK_FALSE(r.ok);
    CHECK(r.error.rfind("bad.toml:2:", 0) == 0);
}
