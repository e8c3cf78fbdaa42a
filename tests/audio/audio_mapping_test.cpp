// Audio features through the mapping, like a knob: `audio = "bass"` entries with gain, curve,
// attack/release; onset/beat pulses on pads; beats that lock the tempo (u_beat). ApplyEvent is
// pure, so no device is needed: the features come from the analyzer on synthetic audio or are
// written by hand.
#include <catch2/catch.hpp>

#include "audio/audio.h"
#include "automation/automation.h"
#include "control/control.h"
#include "signals.h"

using namespace sdfvj;

namespace {

std::vector<ParamDecl> Decls() {
    ParamDecl twist{"twist", ParamType::Float, 0.0f, 0.0f, 4.0f, "Twist"};
    ParamDecl glow{"glow", ParamType::Float, 0.0f, 0.0f, 1.0f, "Glow"};
    ParamDecl flash{"flash", ParamType::Float, 0.0f, 0.0f, 1.0f, "Flash"};
    return {twist, glow, flash};
}

struct Rig {
    Mapping m;
    MappingState ms;
    ParamState p = MakeParamState(Decls());
    MappingActions acts;
    explicit Rig(const std::string& toml) {
        LoadResult r = ParseMapping(toml, "audio.toml", &m);
        INFO(r.error);
        REQUIRE(r.ok);
    }
    float Send(const AudioFeatures& f, double t, const char* param = "twist") {
        acts.Clear();
        ApplyEvent(m, ms, AudioFeatureEvent(f, t), p, &acts);
        return p.target[size_t(FindParam(p, param))];
    }
};

AudioFeatures Bass(float v) {
    AudioFeatures f;
    f.bass = v;
    return f;
}

std::string ParseError(const std::string& toml) {
    Mapping m;
    LoadResult r = ParseMapping(toml, "audio.toml", &m);
    CHECK_FALSE(r.ok);
    return r.error;
}

}  // namespace

TEST_CASE("audio mapping: a feature drives a parameter like a knob", "[audio]") {
    Rig rig("[[map]]\naudio = \"bass\"\ntarget = \"twist\"\n");
    CHECK(rig.m.entries[0].kind == SourceKind::Audio);
    CHECK(rig.m.entries[0].audio == AudioFeature::Bass);
    CHECK(rig.Send(Bass(0.5f), 0.0) == Approx(2.0f));   // half of 0..4
    CHECK(rig.Send(Bass(1.0f), 0.1) == Approx(4.0f));
    CHECK(rig.Send(Bass(0.0f), 0.2) == Approx(0.0f));
    // Other features of the same event leave it alone; the event is no "unmatched" control.
    AudioFeatures f = Bass(0.25f);
    f.high = 1.0f;
    CHECK(rig.Send(f, 0.3) == Approx(1.0f));
    CHECK(rig.ms.unmatched == 0);
}

TEST_CASE("audio mapping: gain, range and curve shape the feature", "[audio]") {
    Rig rig("[[map]]\naudio = \"level\"\ntarget = \"twist\"\ngain = 2.0\nrange = [1.0, 3.0]\n"
            "[[map]]\naudio = \"mid\"\ntarget = \"glow\"\ncurve = \"exponential\"\n");
    AudioFeatures f;
    f.level = 0.25f;
    f.mid = 0.5f;
    CHECK(rig.Send(f, 0.0) == Approx(2.0f));             // 0.25 * 2 = 0.5 of 1..3
    CHECK(rig.p.target[1] == Approx(ApplyCurve(Curve::Exponential, 0.5f, -1.0f)));
    CHECK(rig.p.target[1] < 0.5f);
    f.level = 0.9f;                                       // 1.8: clamped to the top
    CHECK(rig.Send(f, 0.1) == Approx(3.0f));
}

TEST_CASE("audio mapping: attack and release follow the event times", "[audio]") {
    Rig rig("[[map]]\naudio = \"bass\"\ntarget = \"glow\"\nattack = 0.1\nrelease = 0.5\n");
    const double dt = 1.0 / 60.0;
    double t = 0.0;
    rig.Send(Bass(0.0f), t, "glow");
    // A step up: after 0.1 s (the attack) the envelope is at 1 - 1/e.
    float v = 0;
    for (int i = 0; i < 6; ++i) v = rig.Send(Bass(1.0f), t += dt, "glow");
    CHECK(v == Approx(1.0f - std::exp(-1.0f)).margin(1e-4f));
    for (int i = 0; i < 60; ++i) v = rig.Send(Bass(1.0f), t += dt, "glow");
    CHECK(v > 0.999f);
    // A step down falls five times slower: after 0.1 s it has only fallen by 1 - e^-0.2.
    for (int i = 0; i < 6; ++i) v = rig.Send(Bass(0.0f), t += dt, "glow");
    CHECK(v == Approx(std::exp(-0.2f)).margin(1e-3f));
    // No attack/release: the value jumps.
    Rig instant("[[map]]\naudio = \"bass\"\ntarget = \"glow\"\n");
    instant.Send(Bass(0.0f), 0.0, "glow");
    CHECK(instant.Send(Bass(1.0f), dt, "glow") == 1.0f);
}

TEST_CASE("audio mapping: onsets press pads, beats tap the tempo", "[audio]") {
    Rig rig("[[pad]]\naudio = \"onset\"\ntarget = \"flash\"\n"
            "[[pad]]\naudio = \"bass\"\naction = \"toggle\"\ntarget = \"glow\"\n"
            "[[pad]]\naudio = \"beat\"\naction = \"tap_tempo\"\n");
    AudioFeatures f;
    f.onset = true;
    CHECK(rig.Send(f, 0.0, "flash") == 1.0f);             // a trigger: high for the onset's frame
    f.onset = false;
    CHECK(rig.Send(f, 0.1, "flash") == 0.0f);
    // A toggle acts on the rising edge only: held bass toggles once.
    f.bass = 0.9f;
    CHECK(rig.Send(f, 0.2, "glow") == 1.0f);
    CHECK(rig.Send(f, 0.3, "glow") == 1.0f);
    f.bass = 0.1f;
    CHECK(rig.Send(f, 0.4, "glow") == 1.0f);
    f.bass = 0.9f;
    CHECK(rig.Send(f, 0.5, "glow") == 0.0f);
    // A beat taps once and carries the detected tempo.
    f.beat = true;
    f.bpm = 128.0f;
    rig.Send(f, 0.6);
    CHECK(rig.acts.tapTempo);
    CHECK(rig.acts.detectedBpm == 128.0f);
    f.beat = false;
    rig.Send(f, 0.7);
    CHECK_FALSE(rig.acts.tapTempo);
}

TEST_CASE("audio mapping: u_beat locks to the beats of a 128 BPM click train", "[audio]") {
    // The live and replay loops' tap handling: TapTempo + TempoState::TapOnBeat at the detected bpm.
    Rig rig("[[pad]]\naudio = \"beat\"\naction = \"tap_tempo\"\n");
    AudioAnalyzer an;
    ShowAutomation show;
    show.tempo.SetBpm(0.0, 90.0);
    const std::vector<float> audio = test::ClickTrain(128.0, 20.0);
    const size_t block = 800;   // 60 fps
    int beatFrames = 0;
    double lastBeatTime = -1;
    for (size_t i = 0; i + block <= audio.size(); i += block) {
        an.Process(audio.data() + i, block);
        const double now = double(i + block) / 48000.0;
        rig.Send(an.TakeFeatures(), now);
        if (rig.acts.tapTempo) {
            show.tap.Tap(now);
            show.tempo.TapOnBeat(now, rig.acts.detectedBpm > 0 ? rig.acts.detectedBpm : show.tap.bpm);
            ++beatFrames;
            lastBeatTime = now;
            // On a beat frame u_beat's phase is a whole beat.
            const double b = show.tempo.Beats(now);
            CHECK(b - std::floor(b) == Approx(0.0).margin(1e-9));
        }
    }
    CHECK(beatFrames >= 30);
    CHECK(show.tempo.bpm == Approx(128.0).margin(2.0));
    // Half a beat after the last beat, the phase is ~0.5.
    const double b = show.tempo.Beats(lastBeatTime + 30.0 / 128.0);
    CHECK(b - std::floor(b) == Approx(0.5).margin(0.05));
}

TEST_CASE("audio mapping: bad audio entries are file:line errors", "[audio]") {
    CHECK(ParseError("[[map]]\naudio = \"bas\"\ntarget = \"twist\"\n") ==
          "audio.toml:2:9: bad value for 'audio', expected one of: level, bass, mid, high, onset, beat, phase, tempo");
    CHECK(ParseError("[[map]]\naudio = 3\ntarget = \"twist\"\n").rfind("audio.toml:2:9: bad value for 'audio'", 0) == 0);
    CHECK(ParseError("[[map]]\ncc = 1\ngain = 2.0\ntarget = \"twist\"\n") ==
          "audio.toml:3:8: 'gain' applies to audio sources only, expected it removed or audio = \"...\"");
    CHECK(ParseError("[[map]]\naudio = \"bass\"\ngain = 0\ntarget = \"twist\"\n") ==
          "audio.toml:3:8: bad value for 'gain', expected a number in (0, 100]");
    CHECK(ParseError("[[map]]\naudio = \"bass\"\nrelease = -1\ntarget = \"twist\"\n") ==
          "audio.toml:3:11: bad value for 'release', expected seconds 0..60");
    CHECK(ParseError("[[map]]\naudio = \"bass\"\ncc = 3\ntarget = \"twist\"\n").find("more than one source") != std::string::npos);
    CHECK(ParseError("[[map]]\naudio = \"bass\"\nattak = 0.1\ntarget = \"twist\"\n").rfind("audio.toml:3:9: unknown key 'attak'", 0) == 0);
    // A damaged feature event is refused with one line; nothing moves.
    Rig rig("[[map]]\naudio = \"bass\"\ntarget = \"twist\"\n");
    ControlEvent e = AudioFeatureEvent(Bass(1.0f), 0.0);
    e.args.resize(4);
    ApplyEvent(rig.m, rig.ms, e, rig.p, &rig.acts);
    CHECK(rig.p.target[0] == 0.0f);
    CHECK(rig.ms.rejected == 1);
    CHECK(rig.ms.lastRejected.rfind("/sdfvj/audio: expected nine float arguments", 0) == 0);
}
