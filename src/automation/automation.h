// automation: scripted presets. Expressions (muparser), LFOs, ADSR envelopes, a cue list on
// bars, the tempo they follow, and morphs between presets.
//
// Usage, per frame (render thread; everything is a function of the show clock and the events,
// so a replayed take renders the same bytes every time):
//   tempo.Advance(now);                                  // tap / MIDI clock / preset bpm
//   for (const ControlEvent& e : events) automation.OnEvent(e);
//   automation.Apply({now, frame, tempo.Beats(now), tempo.bpm}, KnobPositions(map, ms), params, &reports);
//   for (const CueDesc* c : automation.DueCues(tempo.Beats(now))) ...;   // switch presets
//   StepMorph(morph, params, now);
//
// Expressions see: time (s), frame, beat (beats since the show started, fractional), bar
// (beat / 4), bpm, knob1..knob16 (0..1, the mapping's continuous controls in file order),
// env_<name> for each envelope (0..1), and every parameter of the scene by name (its value
// this frame, before the expression). Functions besides muparser's built-ins (sin, cos, abs,
// min, max, sqrt, exp, log, ...): lfo_sine, lfo_tri, lfo_saw, lfo_square, lfo_rand (x in
// cycles: lfo_sine(beat / 4 + 0.25) has a 4-beat period and a quarter-cycle phase; all -1..1,
// lfo_rand holds a random value per cycle), fract(x), clamp(x, a, b), mix(a, b, t),
// smoothstep(a, b, x), step(edge, x), ease(t) (smooth 0..1).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "control/control.h"
#include "core/automation_desc.h"

namespace sdfvj {

// Where the beat is. The beat position stays continuous when the tempo changes.
struct TempoState {
    double bpm = 120.0;
    double originTime = 0.0;       // show time at which `originBeats` was counted
    double originBeats = 0.0;
    bool running = true;           // MIDI clock stop halts the beat
    double Beats(double now) const { return running ? originBeats + (now - originTime) * bpm / 60.0 : originBeats; }
    void SetBpm(double now, double newBpm);    // clamped to 20..400
    // A tap on the beat: the tempo from the taps so far (TapTempo) and the phase snapped so the
    // tap is a whole beat.
    void TapOnBeat(double now, double newBpm);
};

// Tap tempo: the tempo of the last taps on a pad (median gap of up to five; a 2 s pause starts a
// new count). Its bpm goes to TempoState::TapOnBeat.
struct TapTempo {
    double bpm = 120.0;
    double origin = 0.0;            // time of a beat
    std::vector<double> taps;
    void Tap(double now);
    float Phase(double now) const;
};

// MIDI clock (24 pulses a quarter note), start (0xFA), continue (0xFB), stop (0xFC) from any
// input port: the tempo follows the pulses (median of the last 24 gaps).
struct MidiClockFollower {
    std::vector<double> pulses;
    bool seen = false;
    // Returns true when the event was a clock message (applied to `tempo`).
    bool OnEvent(const ControlEvent& e, TempoState& tempo);
};

struct AutomationFrame {
    double time = 0.0;
    int frame = 0;
    double beats = 0.0;
    double bpm = 120.0;
};

// Compiled automation of one preset. Owns the muparser parsers (hence a class).
class Automation {
public:
    Automation();
    ~Automation();
    Automation(const Automation&) = delete;
    Automation& operator=(const Automation&) = delete;
    Automation(Automation&&) noexcept;
    Automation& operator=(Automation&&) noexcept;

    // Compiles every expression against these parameters. False with
    // "presets/x.json:LINE: what is wrong, what was expected"; then nothing changes.
    bool Load(const AutomationDesc& desc, const std::vector<ParamDecl>& decls, std::string* error);
    void Clear();
    // The cue list counts bars from here (the beat at which the preset was applied).
    void Start(double beats);

    // Notes and /sdfvj/env/<name> i 1|0 fire and release envelopes, at the event's time.
    void OnEvent(const ControlEvent& e);
    void Fire(const std::string& envelope, bool on, double time);
    double EnvelopeValue(const std::string& envelope, double now) const;

    // Evaluates every expression into its parameter (target and value: an expression is already
    // continuous, smoothing would only lag it). NaN, Inf and out-of-range results are clamped to
    // the parameter's range; each parameter's first bad result is reported (file:line).
    void Apply(const AutomationFrame& f, const std::vector<float>& knobs, ParamState& params,
               std::vector<std::string>* reports);
    // Cues whose bar was reached since the last call, in order.
    std::vector<CueDesc> DueCues(double beats);

    const AutomationDesc& Desc() const;
    bool Scripted(const std::string& param) const;        // has an expression
    std::string ExpressionText(const std::string& param) const;

    struct Impl;
private:
    std::unique_ptr<Impl> impl_;
};

// The mapping's continuous controls in file order, as knob1..knobN (0..1; 0 until moved). OSC and
// audio-feature entries are not knobs.
std::vector<float> KnobPositions(const Mapping& m, const MappingState& ms);

// A morph of named parameters from where they are to new values.
struct ParamMorph {
    struct Track { std::string name; float from = 0.0f, to = 0.0f; };
    std::vector<Track> tracks;
    double start = 0.0, seconds = 0.0;
    Easing easing = Easing::Smooth;
    bool Active() const { return !tracks.empty(); }
};
float Ease(Easing e, double t);   // 0..1 -> 0..1, Ease(0) = 0, Ease(1) = 1
// Starts a morph of every named value from the parameter's current value; params not named keep
// theirs. seconds <= 0 or Cut: jumps at once.
void StartMorph(ParamMorph& morph, ParamState& params, const std::vector<std::pair<std::string, float>>& values,
                double now, const MorphDesc& how);
// Moves the morphing parameters (target and value) to where the curve is at `now`; the morph
// ends at its end. Parameters an expression drives are left to it.
void StepMorph(ParamMorph& morph, ParamState& params, double now, const Automation* automation = nullptr);

// Everything a show runs its automation with; `live` and `render --replay` share it, so a replayed
// take renders what the show rendered.
struct ShowAutomation {
    Automation automation;
    TempoState tempo;
    MidiClockFollower clock;
    ParamMorph morph;
    TapTempo tap;
};
// Events for envelopes and the MIDI clock.
void FeedAutomation(ShowAutomation& a, const std::vector<ControlEvent>& events);
// One frame: cues due (those that set values start a morph over their beats here; those that
// switch presets are returned for the caller), then expressions, then the morph.
std::vector<CueDesc> StepAutomation(ShowAutomation& a, ParamState& params, const std::vector<float>& knobs, double now,
                                    int frame, std::vector<std::string>* reports);

}  // namespace sdfvj
