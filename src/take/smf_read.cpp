// Standard MIDI File reader: format 0/1 (2 is merged like 1), PPQ with a tempo map taken from
// all tracks, or SMPTE division; running status; SysEx and unknown meta events skipped; our
// FF 7F OSC events decoded. Every read is bounds-checked against the chunk and the file.
//
// Policy (docs/takes.md): a file that was cut short (crash, partial download) is read up to
// the cut with a warning; bytes that cannot be MIDI (bad VLQ, stray data byte, undefined status)
// are an error, because nothing after them can be trusted.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "take/smf_bytes.h"
#include "take/take.h"

namespace sdfvj {
namespace {

struct TimedEvent {
    int64_t tick;
    uint32_t track;
    uint32_t seq;  // order within the track
    ControlEvent event;
};

struct TempoChange {
    int64_t tick;
    uint32_t track;
    uint32_t seq;
    uint32_t microsPerQuarter;
};

enum class Vlq { Ok, Truncated, TooLong };

class SmfParser {
public:
    SmfParser(const uint8_t* data, size_t size, const std::string& name)
        : d_(data), size_(size), name_(name) {}

    TakeReadResult Parse(Take* out);

private:
    std::string At(size_t byte, const std::string& what) const {
        return name_ + ": byte " + std::to_string(byte) + ": " + what;
    }
    void Warn(size_t byte, const std::string& what) {
        if (warnings_.size() < 100) warnings_.push_back(At(byte, what));
        else if (warnings_.size() == 100) warnings_.push_back(name_ + ": more warnings not shown");
    }
    bool Fail(size_t byte, const std::string& what) {
        if (error_.empty()) error_ = At(byte, what);
        return false;
    }
    uint32_t U16(size_t at) const { return uint32_t(d_[at]) << 8 | d_[at + 1]; }
    uint32_t U32(size_t at) const { return uint32_t(U16(at)) << 16 | U16(at + 2); }
    Vlq ReadVlq(size_t* p, size_t end, uint32_t* v) const {
        *v = 0;
        for (int i = 0; i < 4; ++i) {
            if (*p >= end) return Vlq::Truncated;
            const uint8_t b = d_[(*p)++];
            *v = (*v << 7) | (b & 0x7F);
            if ((b & 0x80) == 0) return Vlq::Ok;
        }
        return Vlq::TooLong;
    }
    bool ParseTrack(size_t begin, size_t end, uint32_t track);
    double TicksToSeconds(int64_t tick, size_t* segment) const;

    const uint8_t* d_;
    size_t size_;
    std::string name_;
    std::string error_;
    std::vector<std::string> warnings_;
    std::vector<TimedEvent> events_;
    std::vector<TempoChange> tempos_;
    std::vector<int64_t> endTicks_;  // End-of-Track (or last event) tick of each track

    // Division: ticks per quarter (tempo applies), or SMPTE ticks per second.
    uint32_t ticksPerQuarter_ = 0;
    double smpteTicksPerSecond_ = 0.0;
    // Tempo map in seconds, built after all tracks are read.
    struct Segment { int64_t tick; double seconds; uint32_t micros; };
    std::vector<Segment> segments_;
};

static std::string Hex(uint32_t v) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "0x%02X", v & 0xFF);
    return buf;
}

// Printable form of a chunk type for messages ("MTrk", or "\x00..." for junk).
static std::string ChunkType(const uint8_t* p) {
    std::string s;
    for (int i = 0; i < 4; ++i) {
        if (p[i] >= 32 && p[i] < 127) s += char(p[i]);
        else { char buf[8]; std::snprintf(buf, sizeof buf, "\\x%02X", p[i]); s += buf; }
    }
    return s;
}

TakeReadResult SmfParser::Parse(Take* out) {
    *out = Take{};
    TakeReadResult result;
    auto finish = [&](bool ok) {
        out->warnings = std::move(warnings_);
        result.ok = ok;
        result.error = error_;
        return result;
    };
    if (d_ == nullptr) size_ = 0;
    if (size_ < 4 || std::memcmp(d_, "MThd", 4) != 0)
        return Fail(0, "not a Standard MIDI File (it does not start with \"MThd\")"), finish(false);
    if (size_ < 14) return Fail(size_, "header chunk cut short (" + std::to_string(size_) + " bytes, need 14)"), finish(false);
    const uint32_t headerLength = U32(4);
    if (headerLength < 6) return Fail(4, "header length " + std::to_string(headerLength) + " is less than 6"), finish(false);
    if (headerLength > size_ - 8)
        return Fail(4, "header length " + std::to_string(headerLength) + " runs past the end of the file"), finish(false);
    const uint32_t format = U16(8), declaredTracks = U16(10), division = U16(12);
    if (format > 2) Warn(8, "unknown format " + std::to_string(format) + ", tracks are merged as in format 1");
    if (format == 2) Warn(8, "format 2 (independent sequences): tracks are merged as in format 1");
    if (division & 0x8000) {
        const int fps = -int(int8_t(division >> 8));
        const uint32_t perFrame = division & 0xFF;
        if (fps != 24 && fps != 25 && fps != 29 && fps != 30)
            return Fail(12, "SMPTE division with " + std::to_string(fps) + " frames per second (need 24, 25, 29 or 30)"), finish(false);
        if (perFrame == 0) return Fail(13, "SMPTE division with 0 ticks per frame"), finish(false);
        smpteTicksPerSecond_ = (fps == 29 ? 30000.0 / 1001.0 : double(fps)) * perFrame;
    } else {
        if (division == 0) return Fail(12, "division is 0 ticks per quarter note"), finish(false);
        ticksPerQuarter_ = division;
    }

    size_t pos = 8 + size_t(headerLength);
    uint32_t tracks = 0;
    while (pos < size_) {
        if (size_ - pos < 8) {
            Warn(pos, std::to_string(size_ - pos) + " trailing bytes ignored (too short for a chunk)");
            break;
        }
        const bool isTrack = std::memcmp(d_ + pos, "MTrk", 4) == 0;
        const uint32_t length = U32(pos + 4);
        const size_t available = size_ - pos - 8;
        if (!isTrack) {  // unknown chunks are skipped, as the SMF spec asks
            if (length > available) {
                Warn(pos, "chunk \"" + ChunkType(d_ + pos) + "\" of " + std::to_string(length) +
                              " bytes runs past the end of the file; the rest is ignored");
                break;
            }
            pos += 8 + size_t(length);
            continue;
        }
        size_t end = pos + 8 + size_t(length);
        if (length > available) {
            Warn(pos + 4, "track chunk length " + std::to_string(length) + " runs past the end of the file (" +
                              std::to_string(available) + " bytes there); reading what is there");
            end = size_;
        }
        if (!ParseTrack(pos + 8, end, tracks)) return finish(false);
        ++tracks;
        if (length > available) break;
        pos = end;
    }
    if (tracks == 0) return Fail(pos, "no track chunk (\"MTrk\") in the file"), finish(false);
    if (tracks != declaredTracks)
        Warn(10, "header declares " + std::to_string(declaredTracks) + " tracks, the file holds " + std::to_string(tracks));
    if (format == 0 && tracks > 1) Warn(8, "format 0 file with " + std::to_string(tracks) + " tracks; all are read");

    // Merge tracks by tick; equal ticks keep track order, then file order.
    auto byTime = [](const auto& a, const auto& b) {
        if (a.tick != b.tick) return a.tick < b.tick;
        if (a.track != b.track) return a.track < b.track;
        return a.seq < b.seq;
    };
    std::sort(events_.begin(), events_.end(), byTime);
    std::sort(tempos_.begin(), tempos_.end(), byTime);
    if (ticksPerQuarter_ != 0) {
        segments_.push_back({0, 0.0, 500000});  // SMF default: 120 BPM until the first tempo event
        for (const TempoChange& t : tempos_) {
            size_t last = segments_.size() - 1;
            const double at = TicksToSeconds(t.tick, &last);
            if (segments_.back().tick == t.tick) segments_.back().micros = t.microsPerQuarter;
            else segments_.push_back({t.tick, at, t.microsPerQuarter});
        }
    }
    out->events.reserve(events_.size());
    size_t segment = 0;
    for (TimedEvent& e : events_) {
        e.event.time = TicksToSeconds(e.tick, &segment);
        out->events.push_back(std::move(e.event));
    }
    int64_t endTick = 0;
    for (int64_t t : endTicks_) endTick = std::max(endTick, t);
    segment = 0;
    out->duration = TicksToSeconds(endTick, &segment);
    if (!out->events.empty()) out->duration = std::max(out->duration, out->events.back().time);
    return finish(true);
}

// Ticks -> seconds through the tempo map. *segment is a search hint: calls with rising ticks
// walk the map once.
double SmfParser::TicksToSeconds(int64_t tick, size_t* segment) const {
    if (ticksPerQuarter_ == 0) return double(tick) / smpteTicksPerSecond_;
    size_t s = std::min(*segment, segments_.size() - 1);
    if (segments_[s].tick > tick) s = 0;
    while (s + 1 < segments_.size() && segments_[s + 1].tick <= tick) ++s;
    *segment = s;
    const Segment& g = segments_[s];
    // Exact for a single tempo (0 + n*micros / (ppq*1e6), one rounding): round trips are tick-exact.
    return g.seconds + double(tick - g.tick) * double(g.micros) / (double(ticksPerQuarter_) * 1.0e6);
}

bool SmfParser::ParseTrack(size_t begin, size_t end, uint32_t track) {
    const std::string trackName = "track " + std::to_string(track + 1);
    size_t p = begin;
    int64_t tick = 0;
    uint8_t running = 0;
    uint32_t seq = 0;
    auto cutShort = [&](size_t at) {
        Warn(at, trackName + " is cut short in the middle of an event; events up to here are kept");
        endTicks_.push_back(tick);
        return true;
    };
    while (p < end) {
        const size_t eventStart = p;
        uint32_t delta = 0;
        const Vlq v = ReadVlq(&p, end, &delta);
        if (v == Vlq::Truncated) return cutShort(eventStart);
        if (v == Vlq::TooLong) return Fail(eventStart, "delta time is a variable-length number longer than 4 bytes");
        tick += delta;
        if (p >= end) return cutShort(eventStart);
        const size_t statusAt = p;
        const uint8_t b = d_[p];
        if (b == 0xFF || b == 0xF0 || b == 0xF7) {
            ++p;
            uint8_t metaType = 0;
            if (b == 0xFF) {
                if (p >= end) return cutShort(eventStart);
                metaType = d_[p++];
            }
            uint32_t length = 0;
            const size_t lengthAt = p;
            const Vlq lv = ReadVlq(&p, end, &length);
            if (lv == Vlq::Truncated) return cutShort(eventStart);
            if (lv == Vlq::TooLong) return Fail(lengthAt, "event length is a variable-length number longer than 4 bytes");
            if (length > end - p) return cutShort(eventStart);
            const uint8_t* body = d_ + p;
            p += length;
            if (b == 0xF7 && length >= 1 && length <= 3 && body[0] > 0xF0 && body[0] != 0xF7 &&
                (length < 2 || body[1] < 0x80) && (length < 3 || body[2] < 0x80)) {
                // An "escaped" system message (MIDI clock, song position...), as the recorder writes them.
                TimedEvent t{tick, track, seq++, {}};
                t.event.source = EventSource::Midi;
                std::memcpy(t.event.midi, body, length);
                t.event.midiSize = uint8_t(length);
                events_.push_back(std::move(t));
                continue;
            }
            if (b != 0xFF) continue;  // SysEx: skipped
            if (metaType == 0x2F) {   // End-of-Track
                endTicks_.push_back(tick);
                if (p < end) Warn(p, std::to_string(end - p) + " bytes after the End-of-Track of " + trackName + " ignored");
                return true;
            }
            if (metaType == 0x51) {
                const uint32_t micros = length == 3 ? uint32_t(body[0]) << 16 | uint32_t(body[1]) << 8 | body[2] : 0;
                if (micros == 0) Warn(statusAt, "tempo event with length " + std::to_string(length) + " or tempo 0 ignored");
                else tempos_.push_back({tick, track, seq++, micros});
                continue;
            }
            if (metaType == 0x7F && smf::IsOscPayload(body, length)) {
                TimedEvent t{tick, track, seq++, {}};
                std::string why;
                if (smf::DecodeOscPayload(body, length, &t.event, &why)) events_.push_back(std::move(t));
                else Warn(statusAt, "OSC event skipped: " + why);
            }
            continue;  // other meta events: skipped
        }
        uint8_t status = running;
        if (b >= 0x80) {
            if (b > 0xF0) return Fail(statusAt, "status byte " + Hex(b) + " cannot appear in a track");
            status = b;
            running = b;
            ++p;
        } else if (running == 0) {
            return Fail(statusAt, "data byte " + Hex(b) + " with no status byte before it (no running status)");
        }
        const uint8_t kind = status & 0xF0;
        const size_t dataBytes = (kind == 0xC0 || kind == 0xD0) ? 1 : 2;
        if (end - p < dataBytes) return cutShort(eventStart);
        TimedEvent t{tick, track, seq++, {}};
        t.event.source = EventSource::Midi;
        t.event.midi[0] = status;
        for (size_t i = 0; i < dataBytes; ++i) {
            const uint8_t data = d_[p + i];
            if (data >= 0x80)
                return Fail(p + i, "data byte " + Hex(data) + " has its top bit set (in a " + Hex(status) + " message)");
            t.event.midi[1 + i] = data;
        }
        t.event.midiSize = uint8_t(1 + dataBytes);
        p += dataBytes;
        events_.push_back(std::move(t));
    }
    Warn(end, trackName + " has no End-of-Track event (file cut short?); all its events are kept");
    endTicks_.push_back(tick);
    return true;
}

}  // namespace

TakeReadResult ParseTake(const uint8_t* data, size_t size, const std::string& name, Take* out) {
    return SmfParser(data, size, name).Parse(out);
}

TakeReadResult ReadTake(const std::string& path, Take* out) {
    constexpr std::streamoff kMaxBytes = 64 << 20;
    *out = Take{};
    std::ifstream file(path, std::ios::binary | std::ios::ate);
    if (!file) return {false, path + ": cannot open for reading"};
    const std::streamoff size = file.tellg();
    if (size < 0) return {false, path + ": cannot read"};
    if (size > kMaxBytes) return {false, path + ": " + std::to_string(size) + " bytes is too large for a take (64 MiB at most)"};
    std::vector<uint8_t> bytes(static_cast<size_t>(size));
    file.seekg(0);
    if (size > 0 && !file.read(reinterpret_cast<char*>(bytes.data()), size)) return {false, path + ": read failed"};
    return ParseTake(bytes.data(), bytes.size(), path, out);  // messages name the path as given
}

}  // namespace sdfvj
