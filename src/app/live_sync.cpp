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

MtcSync LiveSync::LeaderClockSync() {
    MtcSync s;
    s.name = "leader";
    s.pulse = "/sdfvj/clock";
    s.lostSeconds = 0.5;            // a leader sends every frame; a slow frame or two is not a loss
    s.freewheelSeconds = 1e12;      // a lost leader: run on by ourselves until it is back
    return s;
}

namespace {

bool Heard(const MtcSync& m) { return m.state == MtcSync::State::Locked || m.state == MtcSync::State::Holding; }

// One /sdfvj/clock: the leader's time as it sent it (at its frame's start, a moment before it
// arrived here at `local`). Stopped is a hold, said once per place it stops at.
void OnLeaderClock(LiveSync& s, const LeaderClock& c, double local) {
    ++s.leaderFrames;
    s.leaderValues = c.values;
    MtcSync& m = s.leader;
    // Read late: a running leader's time that went on from the last one taken, but by less than
    // this machine's clock did (a stall here, in the frame loop or the input thread, queued the
    // leader's frames and they arrive together). The leader did not step back: the clock runs
    // on from the last anchor, no seek; the frames still say the leader is alive. Only for as
    // long as a leader may go unheard (lostSeconds): a leader that stays behind longer seeks.
    if (c.running && m.state == MtcSync::State::Locked && m.direction > 0) {
        const double behind = MtcShowTime(m, local) - c.seconds;
        if (behind > MtcSeekSeconds(m) && c.seconds >= m.anchorShow && local - m.anchorLocal <= m.lostSeconds) {
            ++s.lateFrames;
            MtcOnQuarterFrame(m, local);
            return;
        }
    }
    if (c.running) {
        MtcOnQuarterFrame(m, local);
        MtcOnTimecode(m, c.seconds, MtcRate::Fps25, local, false);
    } else if (m.state != MtcSync::State::Holding || m.anchorShow != c.seconds) {
        MtcOnTimecode(m, c.seconds, MtcRate::Fps25, local, true);
    }
}

}  // namespace

double LiveSyncStep(LiveSync& s, std::vector<ControlEvent>* events, double wall, std::vector<std::string>* say) {
    std::vector<ControlEvent> rest;
    rest.reserve(events->size());
    const uint64_t seeks = s.leader.seeks;
    for (ControlEvent& e : *events) {
        uint8_t data = 0;
        Timecode tc;
        double at = 0;
        if (e.source == EventSource::Osc && e.address == "/sdfvj/clock") {
            LeaderClock c;
            std::string why;   // checked by the decoder already; a take's copy is checked again
            if (ParseLeaderClock(e.args, &c, &why)) OnLeaderClock(s, c, e.time);
            else say->push_back("sdfvj live: " + why);
            continue;
        }
        if (s.mode != LiveSync::Mode::Mtc) {
            rest.push_back(std::move(e));
            continue;
        }
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
    MtcTick(s.leader, wall);
    double show = wall;
    if (s.mode == LiveSync::Mode::Mtc) {
        MtcTick(s.mtc, wall);
        show = MtcShowTime(s.mtc, wall);
    } else if (s.leader.state != MtcSync::State::Waiting) {
        show = MtcShowTime(s.leader, wall);
        // Each /sdfvj/clock re-anchors the clock on its arrival, which jitters by the network's
        // and the leader's frame timing: a step back smaller than a seek is held instead.
        if (s.leader.seeks == seeks && s.leader.state == MtcSync::State::Locked && show < s.lastShow &&
            s.lastShow - show < 2.0 / s.leader.fps)
            show = s.lastShow;
    }
    s.lastShow = show;
    if (s.mode == LiveSync::Mode::Mtc || s.leader.state != MtcSync::State::Waiting)
        for (ControlEvent& e : rest) e.time = show;
    *events = std::move(rest);
    for (MtcSync* m : {&s.mtc, &s.leader}) {
        for (std::string& line : m->pending) say->push_back("sdfvj live: " + line);
        m->pending.clear();
    }
    return show;
}

std::string LiveSyncStatus(const LiveSync& s, double wall) {
    std::string line;
    if (s.mode == LiveSync::Mode::Mtc) line = MtcStatusLine(s.mtc, wall);
    if (s.mode == LiveSync::Mode::Clock) line = "tempo and beat follow MIDI clock";
    if (s.leader.state != MtcSync::State::Waiting)
        line += (line.empty() ? "" : "; ") + MtcStatusLine(s.leader, wall) + (s.mode == LiveSync::Mode::Mtc ? " (values only)" : "");
    if (s.lateFrames > 0)   // this machine stalled: the leader's frames queued and were read together
        line += "; " + std::to_string(s.lateFrames) + " leader frames read late";
    return line;
}

bool LiveSyncFollows(const LiveSync& s) {
    return s.mode == LiveSync::Mode::Mtc || s.leader.state != MtcSync::State::Waiting;
}

bool LiveSyncRunning(const LiveSync& s) {
    const MtcSync& m = s.mode == LiveSync::Mode::Mtc ? s.mtc : s.leader;
    if (s.mode != LiveSync::Mode::Mtc && m.state == MtcSync::State::Waiting) return true;   // the wall clock
    return m.state == MtcSync::State::Locked || m.state == MtcSync::State::Freewheel;
}

void FollowLeaderValues(const LiveSync& s, ParamState& params) {
    if (!Heard(s.leader)) return;
    for (const auto& [name, v] : s.leaderValues) {
        const int i = FindParam(params, name);
        if (i >= 0) params.value[(size_t)i] = ClampParam(params.decls[(size_t)i], v);
    }
}

bool LeaderTempo(const LiveSync& s, float* beat, float* bpm) {
    if (!Heard(s.leader)) return false;
    bool found = false;
    for (const auto& [name, v] : s.leaderValues) {
        if (name == kLeaderBeatName) *beat = std::clamp(v, 0.0f, 1.0f), found = true;
        if (name == kLeaderBpmName) *bpm = std::clamp(v, 1.0f, 999.0f), found = true;
    }
    return found;
}

}  // namespace sdfvj
