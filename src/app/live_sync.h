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
#pragma once
#include <string>
#include <vector>

#include "control/mtc.h"
#include "core/control_event.h"

namespace sdfvj {

struct LiveSync {
    enum class Mode { Wall, Mtc, Clock };
    Mode mode = Mode::Wall;
    MtcReader reader;
    MtcSync mtc;
};

// "" or "wall" -> Wall, "mtc", "clock"; false with *error for anything else.
bool ParseSyncMode(const std::string& text, LiveSync::Mode* mode, std::string* error);
// Feeds the frame's events: MTC events are taken out (they set the clock), the others are
// stamped with the show time (automation reads event times on the show clock). Returns the
// show time of this frame; `wall` itself in Wall and Clock modes. Lines to say go to *say.
double LiveSyncStep(LiveSync& s, std::vector<ControlEvent>* events, double wall, std::vector<std::string>* say);
// One line for the overlay: "" in Wall mode.
std::string LiveSyncStatus(const LiveSync& s, double wall);

}  // namespace sdfvj
