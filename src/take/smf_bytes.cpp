// Byte-level SMF helpers and the OSC-in-meta-event payload (layout in docs/takes.md).
#include "take/smf_bytes.h"

#include <cmath>
#include <cstring>

#include "take/take.h"

namespace sdfvj::smf {

void PutU16(std::vector<uint8_t>* out, uint32_t v) {
    out->push_back(uint8_t(v >> 8));
    out->push_back(uint8_t(v));
}

void PutU32(std::vector<uint8_t>* out, uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out->push_back(uint8_t(v >> shift));
}

void PutVlq(std::vector<uint8_t>* out, uint32_t v) {
    uint8_t bytes[4];
    int n = 0;
    do {
        bytes[n++] = uint8_t(v & 0x7F);
        v >>= 7;
    } while (v != 0 && n < 4);
    while (n-- > 0) out->push_back(bytes[n] | (n > 0 ? 0x80 : 0x00));
}

std::vector<uint8_t> HeaderChunk() {
    std::vector<uint8_t> h = {'M', 'T', 'h', 'd'};
    PutU32(&h, 6);
    PutU16(&h, 0);  // format 0
    PutU16(&h, 1);  // one track
    PutU16(&h, kTakeTicksPerQuarter);
    return h;
}

std::vector<uint8_t> TrackPrologue(const std::string& trackName) {
    std::vector<uint8_t> t = {0x00, 0xFF, 0x51, 0x03, uint8_t(kTakeTempoMicroseconds >> 16),
                              uint8_t(kTakeTempoMicroseconds >> 8), uint8_t(kTakeTempoMicroseconds)};
    const std::string name = trackName.empty() ? std::string("sdfvj take") : trackName;
    t.insert(t.end(), {0x00, 0xFF, 0x03});
    PutVlq(&t, uint32_t(name.size()));
    t.insert(t.end(), name.begin(), name.end());
    return t;
}

// Emits empty text events until the remaining delta fits one VLQ; returns that remainder.
static uint32_t PutLongDelta(std::vector<uint8_t>* out, int64_t delta) {
    if (delta < 0) delta = 0;
    while (delta > int64_t(kMaxVlq)) {
        PutVlq(out, kMaxVlq);
        out->insert(out->end(), {0xFF, 0x01, 0x00});
        delta -= kMaxVlq;
    }
    return uint32_t(delta);
}

// Data bytes that follow a status byte in a channel message (0x8n..0xEn).
static int ChannelDataBytes(uint8_t status) {
    const uint8_t kind = status & 0xF0;
    return (kind == 0xC0 || kind == 0xD0) ? 1 : 2;
}

bool PutEvent(std::vector<uint8_t>* out, int64_t deltaTicks, const ControlEvent& e) {
    if (e.source == EventSource::Osc) {
        std::vector<uint8_t> payload;
        EncodeOscPayload(e, &payload);
        PutVlq(out, PutLongDelta(out, deltaTicks));
        out->insert(out->end(), {0xFF, 0x7F});
        PutVlq(out, uint32_t(payload.size()));
        out->insert(out->end(), payload.begin(), payload.end());
        return true;
    }
    const size_t n = e.midiSize;
    if (n == 0 || n > 3) return false;
    const uint8_t status = e.midi[0];
    if (status < 0x80) return false;  // running status must be resolved by the input side
    for (size_t i = 1; i < n; ++i)
        if (e.midi[i] >= 0x80) return false;
    if (status < 0xF0) {
        if (n != size_t(1 + ChannelDataBytes(status))) return false;
        PutVlq(out, PutLongDelta(out, deltaTicks));
        out->insert(out->end(), e.midi, e.midi + n);
        return true;
    }
    if (status == 0xF0 || status == 0xF7) return false;  // SysEx does not fit a ControlEvent
    // System common / real-time (MIDI clock, song position...): an F7 "escape" packet.
    PutVlq(out, PutLongDelta(out, deltaTicks));
    out->push_back(0xF7);
    PutVlq(out, uint32_t(n));
    out->insert(out->end(), e.midi, e.midi + n);
    return true;
}

void PutEndOfTrack(std::vector<uint8_t>* out, int64_t deltaTicks) {
    PutVlq(out, PutLongDelta(out, deltaTicks));
    out->insert(out->end(), {0xFF, 0x2F, 0x00});
}

int64_t SecondsToTicks(double seconds) {
    if (!(seconds > 0.0)) return 0;  // also NaN
    const double ticks = std::round(seconds / kTakeSecondsPerTick);
    return ticks > 9.0e15 ? int64_t(9.0e15) : int64_t(ticks);
}

// ---- OSC payload -------------------------------------------------------------------------

static void PutPaddedString(std::vector<uint8_t>* out, const std::string& s) {
    out->insert(out->end(), s.begin(), s.end());
    out->push_back(0);
    while (out->size() % 4 != 0) out->push_back(0);
}

static void PutU64(std::vector<uint8_t>* out, uint64_t v) {
    PutU32(out, uint32_t(v >> 32));
    PutU32(out, uint32_t(v));
}

void EncodeOscPayload(const ControlEvent& e, std::vector<uint8_t>* payload) {
    std::vector<uint8_t> osc;  // a plain OSC 1.0 message, 4-byte aligned from its own start
    PutPaddedString(&osc, e.address);
    std::string tags = ",";
    for (const OscArg& a : e.args) {
        const char t = a.type;
        tags += std::strchr("ifsSbhtdcrmTFNI", t) != nullptr && t != 0 ? t : 'N';
    }
    PutPaddedString(&osc, tags);
    for (size_t k = 0; k < e.args.size(); ++k) {
        const OscArg& a = e.args[k];
        switch (tags[k + 1]) {
            case 'i': case 'c': case 'r': case 'm': PutU32(&osc, uint32_t(a.i)); break;
            case 'f': {
                uint32_t bits;
                std::memcpy(&bits, &a.f, 4);
                PutU32(&osc, bits);
                break;
            }
            case 's': case 'S': PutPaddedString(&osc, a.s); break;
            case 'b':
                PutU32(&osc, uint32_t(a.s.size()));
                osc.insert(osc.end(), a.s.begin(), a.s.end());
                while (osc.size() % 4 != 0) osc.push_back(0);
                break;
            case 'h': case 't': PutU64(&osc, uint64_t(int64_t(a.i))); break;
            case 'd': {
                const double d = a.f;
                uint64_t bits;
                std::memcpy(&bits, &d, 8);
                PutU64(&osc, bits);
                break;
            }
            default: break;  // T F N I carry no data
        }
    }
    payload->assign(std::begin(kOscPrefix), std::end(kOscPrefix));
    payload->insert(payload->end(), osc.begin(), osc.end());
}

bool IsOscPayload(const uint8_t* p, size_t n) {
    return n >= sizeof(kOscPrefix) && std::memcmp(p, kOscPrefix, sizeof(kOscPrefix)) == 0;
}

namespace {
// Bounds-checked reader over the OSC part of a payload.
struct OscReader {
    const uint8_t* p;
    size_t n;
    size_t at = 0;

    bool String(std::string* s) {
        const void* nul = at < n ? std::memchr(p + at, 0, n - at) : nullptr;
        if (nul == nullptr) return false;
        const size_t len = size_t(static_cast<const uint8_t*>(nul) - (p + at));
        s->assign(reinterpret_cast<const char*>(p + at), len);
        at += (len + 4) & ~size_t(3);  // NUL plus padding to 4
        if (at > n) at = n;            // lenient about missing final padding
        return true;
    }
    bool U32(uint32_t* v) {
        if (n - at < 4) return false;
        *v = uint32_t(p[at]) << 24 | uint32_t(p[at + 1]) << 16 | uint32_t(p[at + 2]) << 8 | p[at + 3];
        at += 4;
        return true;
    }
    bool U64(uint64_t* v) {
        uint32_t hi, lo;
        if (!U32(&hi) || !U32(&lo)) return false;
        *v = uint64_t(hi) << 32 | lo;
        return true;
    }
};
}  // namespace

bool DecodeOscPayload(const uint8_t* p, size_t n, ControlEvent* e, std::string* why) {
    e->source = EventSource::Osc;
    e->midiSize = 0;
    e->address.clear();
    e->args.clear();
    OscReader r{p + sizeof(kOscPrefix), n - sizeof(kOscPrefix)};
    if (!r.String(&e->address)) return *why = "OSC address is not terminated", false;
    if (e->address.empty() || e->address[0] != '/') return *why = "OSC address does not start with '/'", false;
    std::string tags;
    if (r.at >= r.n) return true;  // no type tag string: no arguments
    if (!r.String(&tags) || tags.empty() || tags[0] != ',') return *why = "bad OSC type tag string", false;
    for (size_t k = 1; k < tags.size(); ++k) {
        OscArg a;
        a.type = tags[k];
        uint32_t u = 0;
        uint64_t u64 = 0;
        bool ok = true;
        switch (a.type) {
            case 'i': case 'c': case 'r': case 'm': ok = r.U32(&u); a.i = int32_t(u); break;
            case 'f': ok = r.U32(&u); std::memcpy(&a.f, &u, 4); break;
            case 's': case 'S': ok = r.String(&a.s); break;
            case 'b':
                ok = r.U32(&u) && u <= r.n - r.at;
                if (ok) {
                    a.s.assign(reinterpret_cast<const char*>(r.p + r.at), u);
                    r.at += (size_t(u) + 3) & ~size_t(3);
                    if (r.at > r.n) r.at = r.n;
                }
                break;
            case 'h': case 't': ok = r.U64(&u64); a.i = int32_t(int64_t(u64)); break;
            case 'd': {
                ok = r.U64(&u64);
                double d;
                std::memcpy(&d, &u64, 8);
                // Out-of-range double -> float is undefined behaviour: clamp, NaN stays NaN.
                a.f = d != d ? float(d) : float(std::fmax(-3.0e38, std::fmin(3.0e38, d)));
                break;
            }
            case 'T': case 'F': case 'N': case 'I': break;
            default:
                *why = std::string("unknown OSC type tag '") + (a.type >= 32 && a.type < 127 ? a.type : '?') +
                       "'";
                return false;
        }
        if (!ok) return *why = "OSC argument runs past the end of the event", false;
        e->args.push_back(std::move(a));
    }
    return true;
}

}  // namespace sdfvj::smf
