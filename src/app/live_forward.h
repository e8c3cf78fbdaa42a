// `live --forward HOST:PORT[,HOST:PORT...]`: follower nodes. The leader re-sends, as OSC, what its
// show applies, so other `sdfvj live` instances (projectors) show the same state.
//
//   LiveForward fwd;
//   OpenLiveForward("127.0.0.1:9001,10.0.0.7:9000", &fwd, &error);   // Start(); false: exit 2
//   ForwardBeforeControl(fwd, state);                  // each frame, just before ApplyControl
//   ...ApplyControl, ApplyActions...
//   ForwardAfterActions(fwd, state, now);              // sends what changed, and the state once a second
//   ...automation, smoothing...
//   ForwardFrame(fwd, state, now, running);            // the frame: show time and the values it renders
//
// What goes out (the follower's ordinary OSC input takes it; docs/input.md, docs/sync.md):
//   /sdfvj/raw/NAME f TARGET          every parameter target the mapping moved this frame, in the
//                                     parameter's own units (after range, curve, takeover)
//   /sdfvj/preset s FILE              a preset the show switched to (next/prev/index resolved)
//   /sdfvj/effect/NAME i 0|1          an effect toggle
//   /sdfvj/clock iii[sf...]           every frame: the show time (seconds, microseconds), running
//                                     1/0, and the values the frame renders (after automation and
//                                     smoothing); a follower locks its show clock to it and shows
//                                     these values (live_sync.h), so both --log-params agree;
//                                     last "@beat" u_beat and "@bpm" u_bpm
// and once a second the whole state, for a follower started late or a lost packet:
//   /sdfvj/preset ss FILE "state"     the preset on stage; a follower already on it ignores it
//                                     (DropPresetStatesOnStage), any other applies it
//   /sdfvj/effects s LIST             the effect set on stage (as --effects writes it)
//   /sdfvj/raw/NAME f TARGET          every parameter
// Sending never blocks the frame for long (UDP); a target that cannot be resolved is a line at
// start and is skipped.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "app/live_session.h"
#include "core/control_event.h"

namespace sdfvj {

struct ForwardTargets;   // the liblo addresses (live_forward.cpp)

struct LiveForward {
    std::shared_ptr<ForwardTargets> targets;   // null: --forward not given
    std::vector<std::string> names;            // "HOST:PORT" as given, one per target
    std::vector<std::string> paramNames;       // the parameters before ApplyControl, and their targets
    std::vector<float> before;
    std::string presetBefore;                  // the preset on stage before this frame's actions
    double lastState = -1e9;                   // when the whole state last went out
    double stateInterval = 1.0;                // seconds between whole states
    uint64_t sent = 0;                         // messages sent, all targets counted once
    uint64_t frames = 0;                       // /sdfvj/clock frames sent
};

// Parses "HOST:PORT[,HOST:PORT...]" and opens a liblo address for each. "" is no forwarding
// (true). False with one line ("--forward 'x': ..., expected HOST:PORT[,HOST:PORT...]").
bool OpenLiveForward(const std::string& spec, LiveForward* f, std::string* error);
bool IsForwarding(const LiveForward& f);
// Remembers the parameter targets and the preset on stage, so ForwardAfterActions sends only
// what this frame's events changed.
void ForwardBeforeControl(LiveForward& f, const LiveState& state);
// Sends this frame's moved targets, preset switch and effect toggles; the whole state when
// stateInterval has passed since the last one.
void ForwardAfterActions(LiveForward& f, const LiveState& state, double now);
// After smoothing: /sdfvj/clock with the show time, whether the show clock runs (LiveSyncRunning),
// every parameter's value as this frame renders it, then "@beat" BEAT (u_beat) and "@bpm" BPM.
void ForwardFrame(LiveForward& f, const LiveState& state, double show, bool running, float beat, float bpm);
// The leader's clock frames are for the show clock only: the overlay's monitor and a follower's
// --record leave them out (a leader sends one every frame).
bool IsLeaderClock(const ControlEvent& e);

// Follower side: a leader's once-a-second preset state ("/sdfvj/preset ss FILE state") for the
// preset already on stage is dropped, so it does not start that preset over every second. Every
// other event passes unchanged.
void DropPresetStatesOnStage(std::vector<ControlEvent>* events, const std::string& currentPreset);

}  // namespace sdfvj
