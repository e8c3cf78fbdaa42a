// ReplayDriver: turns a recorded take into parameter values on the fixed clock, through the same
// mapping and smoothing as live input, and runs the preset's automation, cues that switch to
// another preset included (TakeShowSwitch). Only the full build has it (it needs the control and
// take modules); the headless build's MakeReplayDriver says so in one line.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <functional>

#include "app/show.h"

namespace sdfvj {

class ReplayDriver {
public:
    virtual ~ReplayDriver() = default;
    virtual double Duration() const = 0;
    // Applies the events before `time`, steps smoothing by dt, writes the current values.
    virtual void Advance(double time, double dt, std::vector<std::pair<std::string, float>>* params) = 0;
    // The tempo the frame at `time` plays at (u_beat phase 0..1, u_bpm).
    virtual float BeatPhase(double time) const = 0;
    virtual float Bpm() const = 0;

    // A cue switched to another preset during the last Advance: the show to render from this
    // frame on (scene, effects, values; its program is not built: GL is the caller's). The values
    // Advance wrote are already the new preset's. A scene change with a morph time crossfades
    // from the old scene's frame (its values frozen) over `fadeSeconds`, as `live` does.
    struct ShowSwitch {
        std::unique_ptr<Show> show;     // null: no switch
        double fadeSeconds = 0.0;       // 0: a cut
        std::function<float(double)> weight;   // seconds since the switch -> 0..1 of the new frame
    };
    virtual ShowSwitch TakeShowSwitch() { return {}; }

    // The audio recorded beside the take (TAKE.wav, docs/audio.md) at `time`: the waveform and
    // spectrum for ISF audio/audioFFT inputs, valid until the next call. False: the take has none.
    virtual bool AudioAt(double /*time*/, std::span<const float>* /*wave*/, std::span<const float>* /*spectrum*/) {
        return false;
    }
};

// `takePath` may be empty: then only the preset's automation runs (a scripted preset renders
// its LFOs, envelopes and cues on the fixed clock).
// `options` are the command line's show options: a preset a cue switches to starts from them
// (--effects, --normals, quality), as in `live`; null = defaults.
std::unique_ptr<ReplayDriver> MakeReplayDriver(const Show& show, const std::string& takePath,
                                               const std::string& mappingPath, std::string* error,
                                               const ShowOptions* options = nullptr);

}  // namespace sdfvj
