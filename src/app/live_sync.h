// `live --sync mtc|clock`: the show clock follows a show-control master.
//
//   LiveSync sync;                                     // mode from --sync (ParseSyncMode)
//   double show = LiveSyncStep(sync, &events, wall, &say);   // once a frame, after draining input
//
// mtc: MIDI Time Code from any input port (control/mtc.h) sets the show clock: automation, u_time,
// the rehearsal take and --log-params's time column run on the master's time; a jump seeks, a
// full frame (locate) holds, a lost master freewheels then stops, each said once (overlay and
// stderr). Until the master is heard the show holds at 0. clock: MIDI clock already drives the
// tempo and beat (automation's MidiClockFollower); the show clock stays the wall clock.
//
// A `--forward` leader (live_forward.h) sends /sdfvj/clock every frame: its show time, running or
// stopped, and the values that frame rendered. In wall and clock modes a show that hears it
// follows it, with no option: the show clock locks to the leader's (MtcSync named "leader": a
// jump seeks, stopped holds, silence for 0.5 s freewheels at speed 1 until the leader is back),
// and FollowLeaderValues puts the leader's rendered values on this frame, so both nodes'
// --log-params agree frame by frame. Under --sync mtc the clock stays MTC's; the values still
// follow.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "control/control.h"
#include "control/mtc.h"
#include "core/control_event.h"

namespace sdfvj {

struct LiveSync {
    enum class Mode { Wall, Mtc, Clock };
    Mode mode = Mode::Wall;
    MtcReader reader;
    MtcSync mtc;
    // The --forward leader's /sdfvj/clock: its clock (state Waiting until heard) and the values of
    // its last frame heard.
    MtcSync leader = LeaderClockSync();
    std::vector<std::pair<std::string, float>> leaderValues;
    double lastShow = -1.0;   // the show time of the last frame (the leader's clock never steps back by jitter)
    uint64_t leaderFrames = 0;
    uint64_t lateFrames = 0;     // of them, read late (a stall here): the clock ran on without them
    static MtcSync LeaderClockSync();
};

// "" or "wall" -> Wall, "mtc", "clock"; false with *error for anything else.
bool ParseSyncMode(const std::string& text, LiveSync::Mode* mode, std::string* error);
// Feeds the frame's events: MTC events are taken out (they set the clock), the others are
// stamped with the show time (automation reads event times on the show clock). Returns the
// show time of this frame; `wall` itself in Wall and Clock modes. Lines to say go to *say.
double LiveSyncStep(LiveSync& s, std::vector<ControlEvent>* events, double wall, std::vector<std::string>* say);
// One line for the overlay: "" in Wall mode with no leader heard.
std::string LiveSyncStatus(const LiveSync& s, double wall);
// True while the show clock follows a master (MTC, or a leader heard): the rehearsal take then
// plays on the show clock.
bool LiveSyncFollows(const LiveSync& s);
// The show clock runs (wall; MTC or a leader locked or freewheeling) or stands (held, stopped):
// what a leader forwards with its time.
bool LiveSyncRunning(const LiveSync& s);
// After smoothing: while the leader is heard (locked or holding), its last frame's values replace
// this frame's, by name (clamped to this scene's ranges; names this scene lacks are skipped).
void FollowLeaderValues(const LiveSync& s, ParamState& params);
// While the leader is heard: the u_beat and u_bpm its last frame rendered with (true); else false
// and *beat, *bpm untouched (this show's own tempo).
bool LeaderTempo(const LiveSync& s, float* beat, float* bpm);

}  // namespace sdfvj
