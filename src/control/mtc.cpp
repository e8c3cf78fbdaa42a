// MIDI Time Code: decoding, encoding and the show clock that follows a master (mtc.h).
#include "control/mtc.h"

#include <cmath>
#include <cstdio>

namespace sdfvj {

namespace {

int NominalFps(MtcRate rate) {
    switch (rate) {
        case MtcRate::Fps24: return 24;
        case MtcRate::Fps25: return 25;
        default: return 30;
    }
}

bool InRange(const Timecode& tc) {
    return tc.hours >= 0 && tc.hours < 24 && tc.minutes >= 0 && tc.minutes < 60 && tc.seconds >= 0 && tc.seconds < 60 &&
           tc.frames >= 0 && tc.frames < NominalFps(tc.rate);
}

// 29.97 drop-frame: frame labels 0 and 1 are skipped at the start of every minute but each
// tenth. Label -> frame count since 00:00:00;00.
long DropFrameCount(const Timecode& tc) {
    const long minutes = tc.hours * 60L + tc.minutes;
    return (minutes * 60 + tc.seconds) * 30L + tc.frames - 2 * (minutes - minutes / 10);
}

}  // namespace

double MtcFramesPerSecond(MtcRate rate) {
    switch (rate) {
        case MtcRate::Fps24: return 24.0;
        case MtcRate::Fps25: return 25.0;
        case MtcRate::Fps2997Drop: return 30000.0 / 1001.0;
        case MtcRate::Fps30: return 30.0;
    }
    return 25.0;
}

const char* MtcRateName(MtcRate rate) {
    switch (rate) {
        case MtcRate::Fps24: return "24";
        case MtcRate::Fps25: return "25";
        case MtcRate::Fps2997Drop: return "29.97df";
        case MtcRate::Fps30: return "30";
    }
    return "?";
}

bool operator==(const Timecode& a, const Timecode& b) {
    return a.hours == b.hours && a.minutes == b.minutes && a.seconds == b.seconds && a.frames == b.frames && a.rate == b.rate;
}

double TimecodeSeconds(const Timecode& tc) {
    if (tc.rate == MtcRate::Fps2997Drop) return DropFrameCount(tc) / MtcFramesPerSecond(tc.rate);
    return (tc.hours * 3600.0 + tc.minutes * 60.0 + tc.seconds) + tc.frames / MtcFramesPerSecond(tc.rate);
}

Timecode TimecodeAt(double seconds, MtcRate rate) {
    Timecode tc;
    tc.rate = rate;
    const double fps = MtcFramesPerSecond(rate);
    long frame = (long)std::floor(seconds * fps + 1e-6);
    if (frame < 0) frame = 0;
    if (rate == MtcRate::Fps2997Drop) {
        // Frame count -> label: 17982 frames per 10 minutes, 1798 per minute after the first.
        const long tens = frame / 17982, rest = frame % 17982;
        frame += 18 * tens + (rest > 1 ? 2 * ((rest - 2) / 1798) : 0);
    }
    const int n = NominalFps(rate);
    tc.frames = int(frame % n);
    const long s = frame / n;
    tc.seconds = int(s % 60);
    tc.minutes = int(s / 60 % 60);
    tc.hours = int(s / 3600 % 24);
    return tc;
}

std::string FormatTimecode(const Timecode& tc) {
    char text[48];
    std::snprintf(text, sizeof text, "%02d:%02d:%02d%c%02d@%s", tc.hours, tc.minutes, tc.seconds,
                  tc.rate == MtcRate::Fps2997Drop ? ';' : ':', tc.frames, MtcRateName(tc.rate));
    return text;
}

std::vector<uint8_t> MtcQuarterFrames(const Timecode& tc, bool reverse) {
    const uint8_t v[8] = {uint8_t(tc.frames & 0x0F), uint8_t((tc.frames >> 4) & 0x01), uint8_t(tc.seconds & 0x0F),
                          uint8_t((tc.seconds >> 4) & 0x03), uint8_t(tc.minutes & 0x0F), uint8_t((tc.minutes >> 4) & 0x03),
                          uint8_t(tc.hours & 0x0F), uint8_t(((tc.hours >> 4) & 0x01) | (uint8_t(tc.rate) << 1))};
    std::vector<uint8_t> out;
    for (int k = 0; k < 8; ++k) {
        const int piece = reverse ? 7 - k : k;
        out.push_back(0xF1);
        out.push_back(uint8_t(piece << 4 | v[piece]));
    }
    return out;
}

std::vector<uint8_t> MtcFullFrame(const Timecode& tc, uint8_t device) {
    return {0xF0, 0x7F, uint8_t(device & 0x7F), 0x01, 0x01, uint8_t(uint8_t(tc.rate) << 5 | (tc.hours & 0x1F)),
            uint8_t(tc.minutes & 0x3F), uint8_t(tc.seconds & 0x3F), uint8_t(tc.frames & 0x1F), 0xF7};
}

bool ParseMtcFullFrame(const uint8_t* b, size_t size, Timecode* out) {
    if (size != 10 || b[0] != 0xF0 || b[1] != 0x7F || b[2] > 0x7F || b[3] != 0x01 || b[4] != 0x01 || b[9] != 0xF7) return false;
    for (size_t i = 5; i < 9; ++i)
        if (b[i] > 0x7F) return false;
    Timecode tc;
    tc.rate = MtcRate((b[5] >> 5) & 0x03);
    tc.hours = b[5] & 0x1F;
    tc.minutes = b[6];
    tc.seconds = b[7];
    tc.frames = b[8];
    if (!InRange(tc)) return false;
    *out = tc;
    return true;
}

ControlEvent MtcFullFrameEvent(const Timecode& tc, double time) {
    ControlEvent e;
    e.time = time;
    e.source = EventSource::Midi;
    e.midi[0] = 0xF0;
    e.midi[1] = 0x7F;
    e.midi[2] = 0x01;
    e.midiSize = 3;
    const std::vector<uint8_t> bytes = MtcFullFrame(tc);
    for (size_t i = 5; i < 9; ++i) {
        OscArg a;
        a.type = 'i';
        a.i = bytes[i];
        e.args.push_back(a);
    }
    return e;
}

MtcEventKind MtcEventOf(const ControlEvent& e, uint8_t* data, Timecode* tc) {
    if (e.source != EventSource::Midi) return MtcEventKind::None;
    if (e.midiSize == 2 && e.midi[0] == 0xF1) {
        *data = e.midi[1];
        return MtcEventKind::QuarterFrame;
    }
    if (e.midiSize == 3 && e.midi[0] == 0xF0 && e.midi[1] == 0x7F && e.midi[2] == 0x01 && e.args.size() == 4) {
        uint8_t b[10] = {0xF0, 0x7F, 0x7F, 0x01, 0x01, 0, 0, 0, 0, 0xF7};
        for (size_t i = 0; i < 4; ++i) {
            if (e.args[i].type != 'i' || e.args[i].i < 0 || e.args[i].i > 0x7F) return MtcEventKind::None;
            b[5 + i] = uint8_t(e.args[i].i);
        }
        if (ParseMtcFullFrame(b, 10, tc)) return MtcEventKind::FullFrame;
    }
    return MtcEventKind::None;
}

bool MtcQuarterFrame(MtcReader& r, uint8_t data, Timecode* out, double* seconds) {
    ++r.quarterFrames;
    const int piece = (data >> 4) & 0x07;
    if (r.next >= 0 && piece != r.next) {   // a lost piece or a change of direction: start over
        ++r.outOfSequence;
        r.next = -1;
    }
    if (r.next < 0) {
        if (piece != 0 && piece != 7) return false;
        r.direction = piece == 0 ? 1 : -1;
        r.have = 0;
    }
    r.nibble[piece] = data & 0x0F;
    ++r.have;
    const bool whole = r.have >= 8 && piece == (r.direction > 0 ? 7 : 0);
    r.next = (piece + r.direction + 8) % 8;
    if (!whole) return false;
    r.have = 0;
    Timecode tc;
    tc.frames = r.nibble[0] | (r.nibble[1] & 0x01) << 4;
    tc.seconds = r.nibble[2] | (r.nibble[3] & 0x03) << 4;
    tc.minutes = r.nibble[4] | (r.nibble[5] & 0x03) << 4;
    tc.hours = r.nibble[6] | (r.nibble[7] & 0x01) << 4;
    tc.rate = MtcRate((r.nibble[7] >> 1) & 0x03);
    if (!InRange(tc)) {
        ++r.outOfSequence;
        return false;
    }
    ++r.timecodes;
    *out = tc;
    if (seconds) *seconds = TimecodeSeconds(tc) + (r.direction > 0 ? 1.75 / MtcFramesPerSecond(tc.rate) : 0.0);
    return true;
}

namespace {

double SeekFrames(const MtcSync& s) { return s.seekFrames > 0 ? s.seekFrames : 2.0; }
double LostSeconds(const MtcSync& s) { return s.lostSeconds > 0 ? s.lostSeconds : 0.25; }
double FreewheelSeconds(const MtcSync& s) { return s.freewheelSeconds > 0 ? s.freewheelSeconds : 2.0; }

// A time as the master names it: a timecode label, or seconds for a master that is not MTC.
std::string At(const MtcSync& s, double seconds, MtcRate rate) {
    if (s.name.empty()) return FormatTimecode(TimecodeAt(seconds, rate));
    char text[48];
    std::snprintf(text, sizeof text, "%.3f s", seconds);
    return text;
}
std::string Name(const MtcSync& s) { return s.name.empty() ? "MTC" : s.name; }
std::string Pulse(const MtcSync& s) { return s.pulse.empty() ? "quarter frame" : s.pulse; }

}  // namespace

double MtcSeekSeconds(const MtcSync& s) { return SeekFrames(s) / s.fps; }

double MtcShowTime(const MtcSync& s, double localTime) {
    if (s.state == MtcSync::State::Locked || s.state == MtcSync::State::Freewheel)
        return std::max(0.0, s.anchorShow + s.direction * (localTime - s.anchorLocal));
    return s.anchorShow;
}

void MtcOnQuarterFrame(MtcSync& s, double localTime) { s.lastQuarter = localTime; }

void MtcOnTimecode(MtcSync& s, double seconds, MtcRate rate, double localTime, bool fullFrame, int direction) {
    const double now = MtcShowTime(s, localTime);
    const MtcSync::State was = s.state;
    s.rate = rate;
    s.fps = MtcFramesPerSecond(rate);
    if (fullFrame) {
        if (was != MtcSync::State::Waiting && std::fabs(seconds - now) > MtcSeekSeconds(s)) ++s.seeks;
        s.pending.push_back(Name(s) + " locate to " + At(s, seconds, rate) + ": holding until the master runs");
        s.state = MtcSync::State::Holding;
    } else {
        const bool running = was == MtcSync::State::Locked || was == MtcSync::State::Freewheel;
        if (running && (std::fabs(seconds - now) > MtcSeekSeconds(s) || direction != s.direction)) {
            ++s.seeks;
            s.pending.push_back(Name(s) + " jump to " + At(s, seconds, rate) + " (from " + At(s, now, rate) + "): seek");
        }
        if (was == MtcSync::State::Waiting) s.pending.push_back(Name(s) + " locked at " + At(s, seconds, rate));
        if (was == MtcSync::State::Freewheel || was == MtcSync::State::Stopped)
            s.pending.push_back((s.name.empty() ? "MTC master" : s.name) + " back at " + At(s, seconds, rate) + ": locked");
        s.state = MtcSync::State::Locked;
        s.direction = direction >= 0 ? 1 : -1;
        s.lastQuarter = localTime;
    }
    s.anchorShow = seconds;
    s.anchorLocal = localTime;
}

void MtcTick(MtcSync& s, double localTime) {
    const double silent = localTime - s.lastQuarter;
    if (s.state == MtcSync::State::Locked && silent > LostSeconds(s)) {
        s.state = MtcSync::State::Freewheel;
        char text[160];
        std::snprintf(text, sizeof text, "%s lost (no %s for %.2f s): freewheeling", Name(s).c_str(), Pulse(s).c_str(),
                      LostSeconds(s));
        s.pending.push_back(text);
    }
    if (s.state == MtcSync::State::Freewheel && silent > LostSeconds(s) + FreewheelSeconds(s)) {
        s.anchorShow = MtcShowTime(s, localTime);
        s.anchorLocal = localTime;
        s.state = MtcSync::State::Stopped;
        s.pending.push_back(Name(s) + " lost for " + std::to_string(int(std::lround(silent))) + " s: stopped at " + At(s, s.anchorShow, s.rate));
    }
}

std::string MtcStatusLine(const MtcSync& s, double localTime) {
    const std::string at = Name(s) + " " + At(s, MtcShowTime(s, localTime), s.rate);
    switch (s.state) {
        case MtcSync::State::Waiting: return Name(s) + ": waiting for the master's timecode";
        case MtcSync::State::Locked: return at + (s.direction < 0 ? " locked (backwards)" : " locked");
        case MtcSync::State::Holding: return at + " holding (master located, not running)";
        case MtcSync::State::Freewheel: return at + " master lost: freewheeling";
        case MtcSync::State::Stopped: return at + " master lost: stopped";
    }
    return at;
}

}  // namespace sdfvj
