// Scripted presets without a device or GL: everything is a function of the clock and the events.
#include <catch2/catch.hpp>

#include <cmath>

#include "automation/automation.h"

using namespace sdfvj;

namespace {

ParamDecl Decl(const std::string& name, float lo, float hi, float def) {
    ParamDecl d;
    d.name = d.label = name;
    d.minValue = lo;
    d.maxValue = hi;
    d.defaultValue = def;
    return d;
}

std::vector<ParamDecl> Decls() { return {Decl("twist", -3, 3, 0.5f), Decl("scale", 0.25f, 2, 1), Decl("glow", 0, 1, 0)}; }

AutomationDesc WithExpression(const std::string& param, const std::string& text, int line = 7) {
    AutomationDesc d;
    d.file = "presets/x.json";
    d.expressions.push_back({param, text, line});
    return d;
}

AutomationFrame At(double beats, double bpm = 120.0) {
    AutomationFrame f;
    f.beats = beats;
    f.bpm = bpm;
    f.time = beats * 60.0 / bpm;
    f.frame = (int)std::lround(f.time * 30.0);
    return f;
}

float Eval(Automation& a, ParamState& p, const AutomationFrame& f, const std::string& param,
           std::vector<std::string>* reports = nullptr) {
    a.Apply(f, {}, p, reports);
    return p.value[(size_t)FindParam(p, param)];
}

}  // namespace

TEST_CASE("automation expression: the issue's example at chosen beats", "[automation]") {
    Automation a;
    std::string err;
    REQUIRE(a.Load(WithExpression("twist", "0.4 + 0.3 * lfo_sine(beat / 4)"), Decls(), &err));
    ParamState p = MakeParamState(Decls());
    CHECK(Eval(a, p, At(0), "twist") == Approx(0.4f));
    CHECK(Eval(a, p, At(1), "twist") == Approx(0.7f));    // a quarter of the 4-beat period: peak
    CHECK(Eval(a, p, At(3), "twist") == Approx(0.1f));    // three quarters: trough
    CHECK(Eval(a, p, At(4), "twist") == Approx(0.4f).margin(1e-5));
    CHECK(p.target[0] == p.value[0]);                     // expressions bypass smoothing
    CHECK(a.Scripted("twist"));
    CHECK_FALSE(a.Scripted("scale"));
}

TEST_CASE("automation lfos: shapes, phase and random-and-hold", "[automation]") {
    Automation a;
    std::string err;
    ParamState p = MakeParamState(Decls());
    REQUIRE(a.Load(WithExpression("twist", "lfo_tri(beat / 4)"), Decls(), &err));
    CHECK(Eval(a, p, At(0), "twist") == Approx(-1.0f));
    CHECK(Eval(a, p, At(1), "twist") == Approx(0.0f).margin(1e-6));
    CHECK(Eval(a, p, At(2), "twist") == Approx(1.0f));
    REQUIRE(a.Load(WithExpression("twist", "lfo_saw(beat / 2 + 0.25)"), Decls(), &err));
    CHECK(Eval(a, p, At(0), "twist") == Approx(-0.5f));
    CHECK(Eval(a, p, At(1), "twist") == Approx(0.5f));
    REQUIRE(a.Load(WithExpression("twist", "lfo_square(beat)"), Decls(), &err));
    CHECK(Eval(a, p, At(0.25), "twist") == 1.0f);
    CHECK(Eval(a, p, At(0.75), "twist") == -1.0f);
    REQUIRE(a.Load(WithExpression("twist", "lfo_rand(bar)"), Decls(), &err));
    const float r0 = Eval(a, p, At(0.5), "twist");
    CHECK(Eval(a, p, At(3.9), "twist") == r0);            // held for the whole bar
    const float r1 = Eval(a, p, At(4.1), "twist");
    CHECK(r1 != r0);                                      // a new value each bar ...
    Automation b;
    REQUIRE(b.Load(WithExpression("twist", "lfo_rand(bar)"), Decls(), &err));
    ParamState q = MakeParamState(Decls());
    CHECK(Eval(b, q, At(4.1), "twist") == r1);            // ... the same on every run
    CHECK(std::fabs(r0) <= 1.0f);
}

TEST_CASE("automation variables: time, frame, bar, bpm, knobs and other parameters", "[automation]") {
    Automation a;
    std::string err;
    AutomationDesc d = WithExpression("glow", "knob2 * 0.5 + step(8, bar) * 0.25");
    d.expressions.push_back({"twist", "scale * 2 + bpm / 1000 + frame * 0", 8});
    REQUIRE(a.Load(d, Decls(), &err));
    ParamState p = MakeParamState(Decls());
    a.Apply(At(4), {0.1f, 0.6f}, p, nullptr);
    CHECK(p.value[2] == Approx(0.3f));
    CHECK(p.value[0] == Approx(2.12f));
    a.Apply(At(40), {0.1f, 1.0f}, p, nullptr);
    CHECK(p.value[2] == Approx(0.75f));
}

TEST_CASE("automation bad expressions: file:line with what was expected, nothing changes", "[automation]") {
    Automation a;
    std::string err;
    REQUIRE(a.Load(WithExpression("twist", "beat"), Decls(), &err));
    CHECK_FALSE(a.Load(WithExpression("twist", "0.4 + * lfo_sine(beat)", 12), Decls(), &err));
    CHECK(err.rfind("presets/x.json:12: expression for 'twist' does not parse", 0) == 0);
    CHECK(err.find("expected") != std::string::npos);
    CHECK_FALSE(a.Load(WithExpression("twist", "wobble(beat)", 13), Decls(), &err));
    CHECK(err.rfind("presets/x.json:13:", 0) == 0);
    CHECK_FALSE(a.Load(WithExpression("nosuch", "1", 14), Decls(), &err));
    CHECK(err.find("expected one of: twist, scale, glow") != std::string::npos);
    // The last good automation stays.
    ParamState p = MakeParamState(Decls());
    CHECK(Eval(a, p, At(1.5), "twist") == Approx(1.5f));
}

TEST_CASE("automation NaN, Inf and division by zero are clamped and reported once, no NaN reaches a parameter", "[automation]") {
    Automation a;
    std::string err;
    REQUIRE(a.Load(WithExpression("twist", "1 / (beat - 2)", 9), Decls(), &err));
    ParamState p = MakeParamState(Decls());
    std::vector<std::string> reports;
    for (double beat : {0.0, 2.0, 2.0, 3.0}) {
        const float v = Eval(a, p, At(beat), "twist", &reports);
        CHECK(std::isfinite(v));
        CHECK(v >= -3.0f);
        CHECK(v <= 3.0f);
    }
    REQUIRE(reports.size() == 1);
    CHECK(reports[0].rfind("presets/x.json:9: expression for 'twist'", 0) == 0);
    REQUIRE(a.Load(WithExpression("scale", "sqrt(-1)", 10), Decls(), &err));
    CHECK(std::isfinite(Eval(a, p, At(0), "scale", &reports)));
    CHECK(reports.size() == 2);
}

TEST_CASE("automation envelopes: ADSR fired by a note and by OSC, at the events' times", "[automation]") {
    AutomationDesc d = WithExpression("glow", "env_flash");
    EnvelopeDesc e;
    e.name = "flash";
    e.note = 36;
    e.attack = 0.1;
    e.decay = 0.2;
    e.sustain = 0.5;
    e.release = 0.4;
    d.envelopes.push_back(e);
    Automation a;
    std::string err;
    REQUIRE(a.Load(d, Decls(), &err));
    ControlEvent on;
    on.time = 1.0;
    on.midiSize = 3;
    on.midi[0] = 0x99; on.midi[1] = 36; on.midi[2] = 100;   // note on, channel 10
    a.OnEvent(on);
    CHECK(a.EnvelopeValue("flash", 0.9) == 0.0);
    CHECK(a.EnvelopeValue("flash", 1.05) == Approx(0.5));    // half the attack
    CHECK(a.EnvelopeValue("flash", 1.1) == Approx(1.0));
    CHECK(a.EnvelopeValue("flash", 1.2) == Approx(0.75));    // half the decay
    CHECK(a.EnvelopeValue("flash", 2.0) == Approx(0.5));     // sustain
    ControlEvent off = on;
    off.time = 3.0;
    off.midi[0] = 0x89;
    a.OnEvent(off);
    CHECK(a.EnvelopeValue("flash", 3.2) == Approx(0.25));    // half the release
    CHECK(a.EnvelopeValue("flash", 3.5) == 0.0);
    ParamState p = MakeParamState(Decls());
    AutomationFrame f;
    f.time = 1.2;
    a.Apply(f, {}, p, nullptr);
    CHECK(p.value[2] == Approx(0.75f));
    // OSC: /sdfvj/env/flash i 1
    ControlEvent osc;
    osc.source = EventSource::Osc;
    osc.time = 10.0;
    osc.address = "/sdfvj/env/flash";
    OscArg arg;
    arg.type = 'i';
    arg.i = 1;
    osc.args.push_back(arg);
    a.OnEvent(osc);
    CHECK(a.EnvelopeValue("flash", 10.1) == Approx(1.0));
}

TEST_CASE("automation cues: steps on bars, once each, and repeating with loop_bars", "[automation]") {
    AutomationDesc d;
    d.file = "presets/cues.json";
    CueDesc c1; c1.bar = 0; c1.values["twist"] = 1.0f; c1.line = 3;
    CueDesc c2; c2.bar = 8; c2.preset = "walker"; c2.overBeats = 2; c2.line = 4;
    d.cues = {c1, c2};
    Automation a;
    std::string err;
    REQUIRE(a.Load(d, Decls(), &err));
    a.Start(10.0);   // the preset was applied at beat 10: bars count from there
    CHECK(a.DueCues(10.0).size() == 1);           // bar 0 at once
    CHECK(a.DueCues(20.0).empty());
    CHECK(a.DueCues(41.9).empty());
    auto due = a.DueCues(42.0);                    // 32 beats later: bar 8
    REQUIRE(due.size() == 1);
    CHECK(due[0].preset == "walker");
    CHECK(a.DueCues(100.0).empty());

    d.loopBars = 4;
    d.cues = {c1};
    REQUIRE(a.Load(d, Decls(), &err));
    a.Start(0.0);
    int fired = 0;
    for (double beat = 0; beat < 48.0; beat += 0.5) fired += (int)a.DueCues(beat).size();
    CHECK(fired == 3);                             // bars 0, 4 and 8
}

TEST_CASE("automation tempo: tap, preset bpm and MIDI clock keep the beat continuous", "[automation]") {
    TempoState t;
    CHECK(t.Beats(1.0) == Approx(2.0));            // 120 bpm
    t.SetBpm(1.0, 60.0);
    CHECK(t.Beats(1.0) == Approx(2.0));
    CHECK(t.Beats(2.0) == Approx(3.0));
    MidiClockFollower clock;
    ControlEvent e;
    e.midiSize = 1;
    e.midi[0] = 0xFA;                              // start
    e.time = 5.0;
    CHECK(clock.OnEvent(e, t));
    CHECK(t.Beats(5.0) == Approx(0.0));
    e.midi[0] = 0xF8;
    for (int i = 0; i < 48; ++i) {                 // 24 pulses per beat at 150 bpm: 1/60 s apart
        e.time = 5.0 + i / 60.0;
        clock.OnEvent(e, t);
    }
    CHECK(t.bpm == Approx(150.0).epsilon(1e-6));
    e.midi[0] = 0xFC;                              // stop holds the beat
    e.time = 6.0;
    clock.OnEvent(e, t);
    CHECK(t.Beats(9.0) == Approx(t.Beats(6.0)));
}

TEST_CASE("automation morph: values at chosen times with an easing curve", "[automation]") {
    ParamState p = MakeParamState(Decls());
    ParamMorph m;
    MorphDesc how;
    how.seconds = 2.0;
    how.easing = Easing::Linear;
    StartMorph(m, p, {{"twist", 2.5f}, {"scale", 2.0f}}, 10.0, how);
    StepMorph(m, p, 10.0);
    CHECK(p.value[0] == Approx(0.5f));
    StepMorph(m, p, 11.0);
    CHECK(p.value[0] == Approx(1.5f));
    CHECK(p.value[1] == Approx(1.5f));
    StepMorph(m, p, 12.5);
    CHECK(p.value[0] == Approx(2.5f));
    CHECK_FALSE(m.Active());
    how.easing = Easing::Smooth;
    StartMorph(m, p, {{"twist", -0.5f}}, 20.0, how);
    StepMorph(m, p, 20.5);                         // a quarter: smoothstep(0.25) = 0.15625
    CHECK(p.value[0] == Approx(2.5f - 3.0f * 0.15625f));
    how.easing = Easing::Cut;
    StartMorph(m, p, {{"twist", 1.0f}}, 30.0, how);
    CHECK(p.value[0] == 1.0f);
    CHECK_FALSE(m.Active());
}
