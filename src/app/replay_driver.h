// ReplayDriver: turns a recorded take into parameter values on the fixed clock, through the same
// mapping and smoothing as live input. Only the full build has it (it needs the control and take
// modules); the headless build's MakeReplayDriver says so in one line.
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

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
};

// `takePath` may be empty: then only the preset's automation runs (a scripted preset renders
// its LFOs, envelopes and cues on the fixed clock).
std::unique_ptr<ReplayDriver> MakeReplayDriver(const Show& show, const std::string& takePath,
                                               const std::string& mappingPath, std::string* error);

}  // namespace sdfvj
