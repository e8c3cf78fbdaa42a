// AutomationDesc: what a scripted preset asks for, as plain data (the scene module parses it out
// of the preset's JSON, the automation module compiles and runs it).
//
//   "bpm": 124,
//   "morph": {"seconds": 2.0, "easing": "smooth"},
//   "params": {"twist": "0.4 + 0.3 * lfo_sine(beat / 4)", "scale": 1.2},
//   "envelopes": {"flash": {"note": 36, "attack": 0.01, "decay": 0.2, "sustain": 0.0, "release": 0.3}},
//   "cues": [{"bar": 8, "preset": "walker", "over": 2}, {"bar": 4, "set": {"twist": 1.0}, "over": 1}],
//   "loop_bars": 16
//
// A number in "params" is a value; a string is an expression evaluated every frame.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace sdfvj {

// One scripted parameter: `param = text`, evaluated every frame.
struct ExpressionDesc {
    std::string param;
    std::string text;
    int line = 0;                  // line of the preset file, for messages
};

// An ADSR envelope: fired by a note (note-on starts, note-off releases) or by OSC
// /sdfvj/env/<name> i 1|0. Its value 0..1 is the variable env_<name> in expressions. Times are
// seconds; sustain is a level.
struct EnvelopeDesc {
    std::string name;
    int note = -1;                 // MIDI note 0..127, -1 = none (OSC only)
    int channel = 0;               // 1..16, 0 = any
    double attack = 0.01, decay = 0.2, sustain = 0.0, release = 0.3;
    int line = 0;
};

// A step of the cue list: at `bar` (0-based, 4 beats a bar), switch to a preset or set values,
// morphing over `overBeats` beats.
struct CueDesc {
    double bar = 0.0;
    std::string preset;            // "" = stay, only set values
    std::map<std::string, float> values;
    double overBeats = 0.0;
    int line = 0;
};

// How a switch to this preset moves every parameter from where it is to its new value.
enum class Easing { Linear, Smooth, EaseIn, EaseOut, Cut };
struct MorphDesc {
    double seconds = 0.0;          // 0 = glide through the per-knob smoothing (as before)
    Easing easing = Easing::Smooth;
    // A switch to another scene: true morphs the two fields in one program (render/field_morph.h),
    // false (or where the scenes cannot share a program) crossfades their frames.
    bool fieldMorph = true;
};

// Parses an easing name: linear, smooth, ease_in, ease_out, cut.
inline bool ParseEasing(const std::string& name, Easing* out) {
    if (name == "linear") *out = Easing::Linear;
    else if (name == "smooth") *out = Easing::Smooth;
    else if (name == "ease_in") *out = Easing::EaseIn;
    else if (name == "ease_out") *out = Easing::EaseOut;
    else if (name == "cut") *out = Easing::Cut;
    else return false;
    return true;
}

struct AutomationDesc {
    std::string file;              // the preset it came from, for messages
    double bpm = 0.0;              // 0 = keep the show's tempo (tap, clock or 120)
    std::vector<ExpressionDesc> expressions;
    std::vector<EnvelopeDesc> envelopes;
    std::vector<CueDesc> cues;
    double loopBars = 0.0;         // > 0: the cue list repeats every loopBars bars
    MorphDesc morph;
    bool Empty() const { return expressions.empty() && envelopes.empty() && cues.empty(); }
};

}  // namespace sdfvj
