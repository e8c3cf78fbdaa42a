// `live --sync`: the show clock from a master's MIDI Time Code (live_sync.h).
#include "app/live_sync.h"

#include <algorithm>

namespace sdfvj {

bool ParseSyncMode(const std::string& text, LiveSync::Mode* mode, std::string* error) {
    if (text.empty() || text == "wall") *mode = LiveSync::Mode::Wall;
    else if (text == "mtc") *mode = LiveSync::Mode::Mtc;
    else if (text == "clock") *mode = LiveSync::Mode::Clock;
    else {
        *error = "--sync " + text + ": expected mtc (MIDI Time Code), clock (MIDI clock: tempo and beat) or wall";
        return false;
    }
    return true;
}

double LiveSyncStep(LiveSync& s, std::vector<ControlEvent>* events, double wall, std::vector<std::string>* say) {
    if (s.mode != LiveSync::Mode::Mtc) return wall;
    std::vector<ControlEvent> rest;
    rest.reserve(events->size());
    for (ControlEvent& e : *events) {
        uint8_t data = 0;
        Timecode tc;
        double at = 0;
        switch (MtcEventOf(e, &data, &tc)) {
            case MtcEventKind::QuarterFrame:
                // The event's own arrival time (input thread), not the frame's: within a frame.
                MtcOnQuarterFrame(s.mtc, e.time);
                if (MtcQuarterFrame(s.reader, data, &tc, &at)) MtcOnTimecode(s.mtc, at, tc.rate, e.time, false, s.reader.direction);
                break;
            case MtcEventKind::FullFrame:
                MtcOnTimecode(s.mtc, TimecodeSeconds(tc), tc.rate, e.time, true);
                break;
            case MtcEventKind::None:
                rest.push_back(std::move(e));
                break;
        }
    }
    MtcTick(s.mtc, wall);
    const double show = MtcShowTime(s.mtc, wall);
    for (ControlEvent& e : rest) e.time = show;
    *events = std::move(rest);
    for (std::string& line : s.mtc.pending) say->push_back("sdfvj live: " + line);
    s.mtc.pending.clear();
    return show;
}

std::string LiveSyncStatus(const LiveSync& s, double wall) {
    if (s.mode == LiveSync::Mode::Mtc) return MtcStatusLine(s.mtc, wall);
    if (s.mode == LiveSync::Mode::Clock) return "tempo and beat follow MIDI clock";
    return "";
}

}  // namespace sdfvj
