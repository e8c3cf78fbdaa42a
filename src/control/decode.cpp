// Decoding on the input threads: MIDI bytes and OSC messages -> ControlEvents. This is the
// code the fuzz target (fuzz_input.cpp) hammers: it must accept any bytes without crashing.
#include <cfloat>
#include <cmath>
#include <cstring>

#include <lo/lo.h>

#include "control/control.h"
#include "control/mtc.h"

namespace sdfvj {
namespace {

int DataBytesFor(uint8_t status) {
    uint8_t t = status & 0xF0;
    return (t == 0xC0 || t == 0xD0) ? 1 : 2;
}

constexpr size_t kMaxOscString = 1024;
constexpr size_t kMaxOscAddress = 256;

}  // namespace

void DecodeMidiBytes(MidiDecoder& d, const uint8_t* bytes, size_t size, double time,
                     std::vector<ControlEvent>* out) {
    for (size_t i = 0; i < size; ++i) {
        uint8_t b = bytes[i];
        if (b >= 0xF8) {             // realtime (clock, start, active sensing...): may appear anywhere
            // Clock, start, continue and stop drive the show's tempo (automation); they do not
            // touch running status. Active sensing, reset and the undefined ones are ignored.
            if (b == 0xF8 || b == 0xFA || b == 0xFB || b == 0xFC) {
                ControlEvent e;
                e.time = time;
                e.source = EventSource::Midi;
                e.midi[0] = b;
                e.midiSize = 1;
                if (out) out->push_back(e);
                ++d.messages;
            } else {
                ++d.ignored;
            }
            continue;
        }
        if (b == 0xF0) {             // SysEx start cancels running status
            d.inSysex = true;
            d.status = 0;
            d.have = d.skip = 0;
            d.sysex[0] = b;
            d.sysexSize = 1;
            ++d.ignored;
            continue;
        }
        if (b == 0xF7) {
            Timecode tc;
            if (d.inSysex && d.sysexSize == 9) {
                d.sysex[9] = b;
                if (ParseMtcFullFrame(d.sysex, 10, &tc)) {   // MTC full frame: a locate
                    --d.ignored;
                    ++d.messages;
                    if (out) out->push_back(MtcFullFrameEvent(tc, time));
                }
            }
            d.inSysex = false;
            d.sysexSize = 0;
            continue;
        }
        if (b >= 0xF1) {             // system common: cancels running status, skip its data
            d.inSysex = false;
            d.status = 0;
            d.have = 0;
            d.skip = (b == 0xF2) ? 2 : (b == 0xF1 || b == 0xF3) ? 1 : 0;
            d.quarterFrame = b == 0xF1;
            if (!d.quarterFrame) ++d.ignored;
            continue;
        }
        if (b >= 0x80) {             // channel status
            d.inSysex = false;
            d.status = b;
            d.have = d.skip = 0;
            continue;
        }
        if (d.inSysex) {
            if (d.sysexSize > 0 && d.sysexSize < 9) d.sysex[d.sysexSize++] = b;
            else d.sysexSize = -1;
            continue;
        }
        if (d.skip > 0) {
            --d.skip;
            if (d.quarterFrame) {     // F1 dd: MIDI Time Code, for --sync mtc (mapping ignores it)
                d.quarterFrame = false;
                ControlEvent e;
                e.time = time;
                e.source = EventSource::Midi;
                e.midi[0] = 0xF1;
                e.midi[1] = b;
                e.midiSize = 2;
                ++d.messages;
                if (out) out->push_back(e);
            }
            continue;
        }
        if (d.status == 0) {
            ++d.stray;
            continue;
        }
        d.data[d.have++] = b;
        if (d.have == DataBytesFor(d.status)) {
            ControlEvent e;
            e.time = time;
            e.source = EventSource::Midi;
            e.midi[0] = d.status;
            e.midi[1] = d.data[0];
            e.midi[2] = d.have > 1 ? d.data[1] : 0;
            e.midiSize = uint8_t(d.have + 1);
            d.have = 0;               // keep status: running status
            ++d.messages;
            if (out) out->push_back(e);
        }
    }
}

bool DecodeOscMessage(const char* path, const char* types, const void* const* argvIn, int argc,
                      double time, ControlEvent* out, std::string* why) {
    auto fail = [&](const std::string& w) {
        if (why) *why = w;
        return false;
    };
    if (!path) return fail("no address");
    size_t plen = strnlen(path, kMaxOscAddress + 1);
    if (plen > kMaxOscAddress) return fail("address longer than 256 characters");
    ControlEvent e;
    e.time = time;
    e.source = EventSource::Osc;
    e.address.assign(path, plen);
    const lo_arg* const* argv = reinterpret_cast<const lo_arg* const*>(argvIn);
    for (int k = 0; k < argc && types && types[k]; ++k) {
        OscArg a;
        a.type = types[k];
        const lo_arg* v = argv ? argv[k] : nullptr;
        if (!v && types[k] != 'T' && types[k] != 'F' && types[k] != 'N' && types[k] != 'I')
            return fail(e.address + ": missing argument data");
        // liblo's argument pointers point into the packet, 4-byte aligned: an 8-byte lo_arg member
        // (or the union itself) must not be read through them. Bytes are copied out instead.
        auto load = [&](auto* out) { std::memcpy(out, static_cast<const void*>(v), sizeof *out); };
        switch (types[k]) {
            case 'f': load(&a.f); break;
            case 'd': {   // out of float's range is infinite (then rejected as not finite), never UB
                double d = 0;
                load(&d);
                a.type = 'f';
                a.f = std::fabs(d) <= FLT_MAX ? float(d) : std::isnan(d) ? NAN : d > 0 ? INFINITY : -INFINITY;
                break;
            }
            case 'i': load(&a.i); a.f = float(a.i); break;
            case 'h': {
                int64_t h = 0;
                load(&h);
                a.type = 'i';
                a.i = int32_t(std::max<int64_t>(INT32_MIN, std::min<int64_t>(INT32_MAX, h)));
                a.f = float(a.i);
                break;
            }
            case 'T': a.type = 'i'; a.i = 1; a.f = 1.0f; break;
            case 'F': a.type = 'i'; a.i = 0; a.f = 0.0f; break;
            case 's': case 'S': {
                a.type = 's';
                const char* s = reinterpret_cast<const char*>(v);
                size_t n = strnlen(s, kMaxOscString + 1);
                if (n > kMaxOscString) return fail(e.address + ": string argument longer than 1024 bytes");
                a.s.assign(s, n);
                break;
            }
            default: break;  // blobs, MIDI, timetags...: kept by tag, ignored
        }
        e.args.push_back(std::move(a));
    }
    // Check the built-in addresses here, on the OSC thread, so junk never reaches the queue.
    const std::string& ad = e.address;
    auto numeric = [&]() { return !e.args.empty() && (e.args[0].type == 'f' || e.args[0].type == 'i'); };
    if (ad.rfind("/sdfvj/", 0) == 0) {
        if (ad.rfind("/sdfvj/param/", 0) == 0 || ad.rfind("/sdfvj/raw/", 0) == 0) {
            if (ad.size() <= (ad[7] == 'p' ? 13u : 11u)) return fail(ad + ": no parameter name in the address");
            if (!numeric()) return fail(ad + ": expected one float argument, got '" + std::string(types ? types : "") + "'");
            if (e.args[0].type == 'f' && !std::isfinite(e.args[0].f)) return fail(ad + ": value is not finite");
        } else if (ad == "/sdfvj/preset") {
            if (e.args.empty() || (e.args[0].type != 's' && e.args[0].type != 'i'))
                return fail(ad + ": expected one string or int argument, got '" + std::string(types ? types : "") + "'");
        } else if (ad.rfind("/sdfvj/effect/", 0) == 0) {
            if (ad.size() <= 14) return fail(ad + ": no effect name in the address");
            if (!numeric()) return fail(ad + ": expected one int argument, got '" + std::string(types ? types : "") + "'");
        } else if (ad.rfind("/sdfvj/env/", 0) == 0) {   // a scripted preset's envelope: 1 fire, 0 release
            if (ad.size() <= 11) return fail(ad + ": no envelope name in the address");
            if (!numeric()) return fail(ad + ": expected one int argument (1 fire, 0 release), got '" + std::string(types ? types : "") + "'");
        } else if (ad == "/sdfvj/effects") {   // a leader's whole effect set, as --effects writes it
            if (e.args.size() != 1 || e.args[0].type != 's')
                return fail(ad + ": expected one string argument (an effect list), got '" + std::string(types ? types : "") + "'");
        } else if (ad == "/sdfvj/clock") {
            std::string w;
            if (!ParseLeaderClock(e.args, nullptr, &w)) return fail(w);
        } else {
            return fail(ad + ": unknown address, expected /sdfvj/param/<name>, /sdfvj/raw/<name>, "
                             "/sdfvj/preset, /sdfvj/effect/<name>, /sdfvj/effects, /sdfvj/env/<name> or /sdfvj/clock");
        }
    }
    if (out) *out = std::move(e);
    return true;
}

bool ParseLeaderClock(const std::vector<OscArg>& args, LeaderClock* out, std::string* why) {
    auto fail = [&](const std::string& w) {
        if (why) *why = "/sdfvj/clock: " + w;
        return false;
    };
    if (args.size() < 3 || args[0].type != 'i' || args[1].type != 'i' || args[2].type != 'i')
        return fail("expected int SECONDS, int MICROSECONDS, int RUNNING (iii), then NAME VALUE pairs");
    if (args[0].i < 0 || args[0].i > kLeaderClockMaxSeconds)
        return fail("seconds " + std::to_string(args[0].i) + " out of range, expected 0.." + std::to_string(kLeaderClockMaxSeconds));
    if (args[1].i < 0 || args[1].i > 999999)
        return fail("microseconds " + std::to_string(args[1].i) + " out of range, expected 0..999999");
    if (args[2].i != 0 && args[2].i != 1) return fail("running " + std::to_string(args[2].i) + ", expected 1 (running) or 0 (stopped)");
    const size_t pairs = (args.size() - 3) / 2;
    if ((args.size() - 3) % 2 != 0 || pairs > 256) return fail("expected at most 256 NAME VALUE pairs after iii");
    LeaderClock c;
    c.seconds = args[0].i + args[1].i * 1e-6;
    c.running = args[2].i == 1;
    for (size_t k = 3; k < args.size(); k += 2) {
        const OscArg& name = args[k];
        const OscArg& value = args[k + 1];
        if (name.type != 's' || name.s.empty() || name.s.size() > 64)
            return fail("argument " + std::to_string(k + 1) + " is not a parameter name, expected a string of 1..64 bytes");
        if (value.type != 'f' && value.type != 'i')
            return fail(name.s.substr(0, 64) + ": expected a float value");
        if (!std::isfinite(value.f)) return fail(name.s.substr(0, 64) + ": value is not finite");
        if (out) c.values.emplace_back(name.s, value.f);
    }
    if (out) *out = std::move(c);
    return true;
}

// The body of the liblo method handler that InputSession registers (Impl::OnOsc): decode,
// count, queue. It lives here so the fuzzer (fuzz_input.cpp) runs exactly what production
// runs behind a real lo_server. Returns false, with *why, for a message sdfvj cannot use.
bool HandleOscMessage(const char* path, const char* types, const void* const* argv, int argc, double time,
                      EventQueue& queue, InputCounters& counters, std::string* why) {
    ControlEvent e;
    if (!DecodeOscMessage(path, types, argv, argc, time, &e, why)) {
        counters.oscWrongType++;
        return false;
    }
    counters.oscMessages++;
    queue.Push(std::move(e));
    return true;
}

namespace {

void DecodeOscElement(const uint8_t* data, size_t size, double time, std::vector<ControlEvent>* out,
                      OscDecodeCounts* c, int depth) {
    if (size >= 8 && std::memcmp(data, "#bundle", 8) == 0) {
        if (depth > 8 || size < 16) { ++c->malformed; return; }
        size_t pos = 16;  // "#bundle\0" + timetag
        while (pos < size) {
            if (size - pos < 4) { ++c->malformed; return; }
            uint32_t n = (uint32_t(data[pos]) << 24) | (uint32_t(data[pos + 1]) << 16) |
                         (uint32_t(data[pos + 2]) << 8) | uint32_t(data[pos + 3]);
            pos += 4;
            if (n > size - pos || n % 4 != 0) { ++c->malformed; return; }
            DecodeOscElement(data + pos, n, time, out, c, depth + 1);
            pos += n;
        }
        return;
    }
    // lo_message_deserialise wants a writable buffer (it byte-swaps in a copy it makes itself,
    // but the prototype is not const).
    std::vector<uint8_t> copy(data, data + size);
    int result = 0;
    lo_message m = copy.empty() ? nullptr : lo_message_deserialise(copy.data(), copy.size(), &result);
    if (!m) { ++c->malformed; return; }
    const char* path = reinterpret_cast<const char*>(copy.data());  // validated by deserialise
    ControlEvent e;
    std::string why;
    if (DecodeOscMessage(path, lo_message_get_types(m),
                         reinterpret_cast<const void* const*>(lo_message_get_argv(m)),
                         lo_message_get_argc(m), time, &e, &why)) {
        ++c->ok;
        if (out) out->push_back(std::move(e));
    } else {
        ++c->wrongType;
    }
    lo_message_free(m);
}

}  // namespace

void DecodeOscPacket(const uint8_t* data, size_t size, double time, std::vector<ControlEvent>* out,
                     OscDecodeCounts* counts) {
    OscDecodeCounts local;
    DecodeOscElement(data, size, time, out, counts ? counts : &local, 0);
}

}  // namespace sdfvj
