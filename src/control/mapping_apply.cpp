// ApplyEvent: one ControlEvent + the mapping -> parameter targets and actions. Pure: all the
// memory it needs between events (14-bit MSBs, NRPN selection, takeover, toggles) lives in
// MappingState, so tests drive it without any device and replays give the same values.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "control/control.h"

namespace sdfvj {

int TargetIndex(const MappingEntry& en, const ParamState& params) {
    if (en.targetIndex > 0) return en.targetIndex <= (int)params.decls.size() ? en.targetIndex - 1 : -1;
    return en.target.empty() ? -1 : FindParam(params, en.target);
}

namespace {

constexpr float kTakeoverTolerance = 1.5f / 127.0f;  // "close enough" for pickup, in 0..1

float DefaultAmount(Curve c, float amount) {
    if (amount > 0.0f) return std::max(amount, 1e-3f);
    return c == Curve::S ? 2.0f : 3.0f;
}

float Clamp01(float x) { return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : (x == x ? x : 0.0f)); }

void OutputRange(const MappingEntry& en, const ParamDecl& d, float* lo, float* hi) {
    *lo = en.hasRange ? en.outMin : d.minValue;
    *hi = en.hasRange ? en.outMax : d.maxValue;
}

// Control position 0..1 -> parameter units.
float Transfer(const MappingEntry& en, const ParamDecl& d, float x) {
    float lo, hi;
    OutputRange(en, d, &lo, &hi);
    x = Clamp01(x);
    if (en.invert) x = 1.0f - x;
    return lo + ApplyCurve(en.curve, x, en.curveAmount) * (hi - lo);
}

// Parameter units -> the control position that would produce them.
float InverseTransfer(const MappingEntry& en, const ParamDecl& d, float v) {
    float lo, hi;
    OutputRange(en, d, &lo, &hi);
    float y = hi != lo ? Clamp01((v - lo) / (hi - lo)) : 0.0f;
    float x = InverseCurve(en.curve, y, en.curveAmount);
    return en.invert ? 1.0f - x : x;
}

void Report(MappingActions* a, const std::string& line) {
    if (a) a->messages.push_back(line);
}

void Reject(MappingState& ms, MappingActions* a, const std::string& why) {
    ++ms.rejected;
    ms.lastRejected = why;
    Report(a, why);
}

void Write(const MappingEntry& en, EntryState& es, ParamState& p, int idx, float v, MappingActions* a) {
    if (!SetParamTarget(p, idx, v)) Report(a, p.lastClamp);
    es.lastWritten = p.target[idx];
    es.wroteOnce = true;
    if (en.smoothing >= 0.0f) p.smoothingTau[idx] = en.smoothing;
}

// A continuous (absolute) control moved to x.
void ApplyAbsolute(const MappingEntry& en, EntryState& es, ParamState& p, int idx, float x,
                   MappingActions* a) {
    const ParamDecl& d = p.decls[idx];
    float cur = p.target[idx];
    // Anything else that moved the parameter (preset, OSC, another mapping) breaks the link.
    if (!es.wroteOnce || cur != es.lastWritten) es.engaged = false;
    if (en.takeover == Takeover::None) es.engaged = true;
    float prev = es.position;
    es.position = x;
    if (!es.engaged) {
        float pos = InverseTransfer(en, d, cur);
        bool close = std::fabs(x - pos) <= kTakeoverTolerance;
        bool crossed = prev >= 0.0f && (prev - pos) * (x - pos) <= 0.0f;
        if (close || crossed) {
            es.engaged = true;
        } else if (en.takeover == Takeover::Scale && prev >= 0.0f && x != prev) {
            // Value scaling: move the parameter the same fraction of the way to the end the
            // control is heading for, so both arrive at the end together.
            float np = x > prev ? pos + (x - prev) * (1.0f - pos) / std::max(1.0f - prev, 1e-6f)
                                : pos - (prev - x) * pos / std::max(prev, 1e-6f);
            np = Clamp01(np);
            if (std::fabs(np - x) <= kTakeoverTolerance) es.engaged = true;
            Write(en, es, p, idx, Transfer(en, d, es.engaged ? x : np), a);
            return;
        } else {
            return;  // pickup: wait until the control reaches the parameter
        }
    }
    Write(en, es, p, idx, Transfer(en, d, x), a);
}

void ApplyRelative(const MappingEntry& en, EntryState& es, ParamState& p, int idx, int ticks,
                   MappingActions* a) {
    if (ticks == 0) return;
    const ParamDecl& d = p.decls[idx];
    float cur = p.target[idx];
    float pos = (es.wroteOnce && cur == es.lastWritten && es.position >= 0.0f)
                    ? es.position : InverseTransfer(en, d, cur);
    float x = Clamp01(pos + float(ticks) * en.step);
    es.position = x;
    es.engaged = true;
    Write(en, es, p, idx, Transfer(en, d, x), a);
}

void ApplyPad(const Mapping& m, size_t ei, MappingState& ms, ParamState& p, bool pressed,
              int sourceNumber, MappingActions* a) {
    const MappingEntry& en = m.entries[ei];
    EntryState& es = ms.entries[ei];
    int idx = TargetIndex(en, p);
    auto needTarget = [&]() {
        if (idx >= 0) return true;
        if (en.targetIndex > 0) return false;   // past the scene's last input: nothing to drive
        Reject(ms, a, "mapping entry at line " + std::to_string(en.line) + ": unknown parameter '" +
                          en.target + "', expected one of: " + ParamNameList(p.decls));
        return false;
    };
    switch (en.action) {
        case PadAction::Trigger:
            if (!needTarget()) return;
            {
                float lo, hi;
                OutputRange(en, p.decls[idx], &lo, &hi);
                if (en.invert) std::swap(lo, hi);
                Write(en, es, p, idx, pressed ? hi : lo, a);
                if (pressed && a) a->triggers.push_back(en.target);
            }
            return;
        case PadAction::Toggle:
            if (!pressed || !needTarget()) return;
            {
                float lo, hi;
                OutputRange(en, p.decls[idx], &lo, &hi);
                if (en.invert) std::swap(lo, hi);
                es.toggled = !es.toggled;
                Write(en, es, p, idx, es.toggled ? hi : lo, a);
            }
            return;
        case PadAction::Preset:
            if (pressed && a) {
                std::string pick = en.preset.empty() ? std::to_string(sourceNumber) : en.preset;
                // With a [profile] presets list, a number picks from that list (a pad keeps its
                // preset when a file is added to presets/); without one, `sdfvj list`'s order.
                const bool number = !pick.empty() && pick.size() < 4 &&
                                    std::all_of(pick.begin(), pick.end(), [](char c) { return c >= '0' && c <= '9'; });
                if (number && !m.presets.empty()) {
                    size_t i = 0;
                    std::from_chars(pick.data(), pick.data() + pick.size(), i);   // 1-3 digits: fits
                    if (i >= m.presets.size()) {
                        Reject(ms, a, "mapping entry at line " + std::to_string(en.line) + ": preset slot " + pick +
                                          " is past the profile's " + std::to_string(m.presets.size()) + " presets");
                        return;
                    }
                    pick = m.presets[i];
                }
                a->presetSelect.push_back(pick);
            }
            return;
        case PadAction::Effect:
            if (pressed) {
                bool on = !ms.effects[en.effect];
                ms.effects[en.effect] = on;
                if (a) a->effectToggles.emplace_back(en.effect, on);
            }
            return;
        case PadAction::TapTempo:
            if (pressed && a) a->tapTempo = true;
            return;
        case PadAction::None:
            return;
    }
}

bool ChannelMatches(const MappingEntry& en, int ch) { return en.channel == 0 || en.channel == ch; }

// The value an event carries for one entry, as a control position 0..1 plus pad state.
struct Reading {
    bool has = false;
    float x = 0.0f;
    bool relative = false;
    int ticks = 0;
    bool pressed = false;
    int number = 0;  // for preset-by-number
};

void Dispatch(const Mapping& m, size_t ei, MappingState& ms, ParamState& p, const Reading& r,
              MappingActions* a) {
    const MappingEntry& en = m.entries[ei];
    if (en.action != PadAction::None) {
        ApplyPad(m, ei, ms, p, r.pressed, r.number, a);
        return;
    }
    int idx = TargetIndex(en, p);
    if (idx < 0 && en.targetIndex > 0) {   // knob 6 on a scene with five inputs: nothing to drive
        ++ms.unmatched;
        return;
    }
    if (idx < 0) {
        Reject(ms, a, "mapping entry at line " + std::to_string(en.line) + ": unknown parameter '" +
                          en.target + "', expected one of: " + ParamNameList(p.decls));
        return;
    }
    if (r.relative)
        ApplyRelative(en, ms.entries[ei], p, idx, r.ticks, a);
    else
        ApplyAbsolute(en, ms.entries[ei], p, idx, r.x, a);
}

// One audio feature event (/sdfvj/audio) for every `audio = "feature"` entry. The envelope runs
// on the events' own times, so a replayed take gives the same values as the show did.
void ApplyAudio(const Mapping& m, MappingState& ms, const ControlEvent& e, ParamState& p, MappingActions* a) {
    AudioFeatures f;
    if (!ReadAudioFeatureEvent(e, &f)) {
        Reject(ms, a, e.address + ": expected nine float arguments (level, levelDb, bass, mid, high, onset, beat, bpm, phase)");
        return;
    }
    for (size_t i = 0; i < m.entries.size(); ++i) {
        const MappingEntry& en = m.entries[i];
        if (en.kind != SourceKind::Audio) continue;
        EntryState& es = ms.entries[i];
        const float raw = Clamp01(f.Value(en.audio) * en.gain);
        const double dt = es.envelopeTime < 0 ? 0.0 : std::max(0.0, e.time - es.envelopeTime);
        const float tau = raw > es.envelope ? en.attack : en.release;
        if (es.envelopeTime < 0 || tau <= 0.0f) es.envelope = raw;
        else es.envelope += (raw - es.envelope) * float(1.0 - std::exp(-dt / double(tau)));
        es.envelopeTime = e.time;
        Reading r;
        r.x = es.envelope;
        // A trigger follows the feature (high while >= 0.5); the other pads act on its rising edge,
        // so a loud bass held for a second toggles once, not sixty times.
        const bool high = raw >= 0.5f;
        r.pressed = en.action == PadAction::Trigger ? high : high && !es.audioHigh;
        es.audioHigh = high;
        if (en.action != PadAction::None && en.action != PadAction::Trigger && !r.pressed) continue;
        Dispatch(m, i, ms, p, r, a);
        // u_beat locked to the music: a beat taps the tempo at the analysis's bpm (steadier than
        // the gaps between frames that carried beats).
        if (en.action == PadAction::TapTempo && a && f.bpm > 0.0f) a->detectedBpm = f.bpm;
    }
}

bool ApplyBuiltinOsc(MappingState& ms, const ControlEvent& e, ParamState& p, MappingActions* a) {
    const std::string& ad = e.address;
    auto number = [&](float* out) {
        if (e.args.empty()) return false;
        const OscArg& g = e.args[0];
        if (g.type == 'f') *out = g.f;
        else if (g.type == 'i') *out = float(g.i);
        else return false;
        return true;
    };
    auto startsWith = [&](const char* pre) { return ad.rfind(pre, 0) == 0; };
    if (startsWith("/sdfvj/param/") || startsWith("/sdfvj/raw/")) {
        bool raw = startsWith("/sdfvj/raw/");
        std::string name = ad.substr(raw ? 11 : 13);
        float v;
        if (!number(&v) || !std::isfinite(v)) {
            Reject(ms, a, ad + ": expected one float argument");
            return true;
        }
        int idx = FindParam(p, name);
        if (idx < 0) {
            Reject(ms, a, ad + ": unknown parameter '" + name + "', expected one of: " + ParamNameList(p.decls));
            return true;
        }
        const ParamDecl& d = p.decls[idx];
        float value = raw ? v : d.minValue + v * (d.maxValue - d.minValue);
        if (!SetParamTarget(p, idx, value)) Report(a, p.lastClamp);
        return true;
    }
    if (ad == "/sdfvj/preset") {
        if (e.args.empty() || (e.args[0].type != 's' && e.args[0].type != 'i')) {
            Reject(ms, a, ad + ": expected one string or int argument");
        } else if (a) {
            a->presetSelect.push_back(e.args[0].type == 's' ? e.args[0].s : std::to_string(e.args[0].i));
        }
        return true;
    }
    if (startsWith("/sdfvj/effect/")) {
        float v;
        std::string name = ad.substr(14);
        if (!number(&v) || name.empty()) {
            Reject(ms, a, ad + ": expected one int argument (1 on, 0 off)");
            return true;
        }
        ms.effects[name] = v != 0.0f;
        if (a) a->effectToggles.emplace_back(name, v != 0.0f);
        return true;
    }
    if (ad == "/sdfvj/clock") return true;   // a leader's frame: the show clock takes it (app/live_sync.h)
    if (ad == "/sdfvj/effects") {   // the whole set (a --forward leader's state): "none," clears first
        if (e.args.size() != 1 || e.args[0].type != 's') Reject(ms, a, ad + ": expected one string argument (an effect list)");
        else if (a) a->effectToggles.emplace_back("none," + e.args[0].s, true);
        return true;
    }
    return false;
}

}  // namespace

float ApplyCurve(Curve c, float x, float amount) {
    x = Clamp01(x);
    float k = DefaultAmount(c, amount);
    switch (c) {
        case Curve::Linear: return x;
        case Curve::Exponential: return float(std::expm1(double(k) * x) / std::expm1(double(k)));
        case Curve::Logarithmic: return float(std::log1p(double(x) * std::expm1(double(k))) / k);
        case Curve::S: {
            double a = std::pow(double(x), double(k)), b = std::pow(1.0 - x, double(k));
            return float(a / (a + b));
        }
    }
    return x;
}

float InverseCurve(Curve c, float y, float amount) {
    y = Clamp01(y);
    float k = DefaultAmount(c, amount);
    switch (c) {
        case Curve::Linear: return y;
        case Curve::Exponential: return ApplyCurve(Curve::Logarithmic, y, k);
        case Curve::Logarithmic: return ApplyCurve(Curve::Exponential, y, k);
        case Curve::S: return ApplyCurve(Curve::S, y, 1.0f / k);
    }
    return y;
}

int DecodeRelative(EncoderMode mode, int v) {
    v &= 0x7F;
    switch (mode) {
        case EncoderMode::Absolute: return 0;
        case EncoderMode::SignedBit: return (v & 0x40) ? -(v & 0x3F) : (v & 0x3F);
        case EncoderMode::SignedBit2: return (v & 0x40) ? (v & 0x3F) : -(v & 0x3F);
        case EncoderMode::BinaryOffset: return v - 64;
        case EncoderMode::TwosComplement: return (v & 0x40) ? v - 128 : v;
    }
    return 0;
}

void ApplyEvent(const Mapping& m, MappingState& ms, const ControlEvent& e, ParamState& p,
                MappingActions* a) {
    if (ms.entries.size() != m.entries.size()) ms.entries.resize(m.entries.size());
    bool used = false;

    if (e.source == EventSource::Osc) {
        if (e.address == kAudioFeatureAddress) {
            ApplyAudio(m, ms, e, p, a);
            return;
        }
        if (e.address.rfind("/sdfvj/", 0) == 0 && ApplyBuiltinOsc(ms, e, p, a)) return;
        for (size_t i = 0; i < m.entries.size(); ++i) {
            const MappingEntry& en = m.entries[i];
            if (en.kind != SourceKind::Osc || en.oscAddress != e.address) continue;
            Reading r;
            if (e.args.empty() || (e.args[0].type != 'f' && e.args[0].type != 'i')) {
                Reject(ms, a, e.address + ": expected one float or int argument");
                return;
            }
            r.x = e.args[0].type == 'f' ? e.args[0].f : float(e.args[0].i);
            if (!std::isfinite(r.x)) r.x = 0.0f;
            r.pressed = r.x >= 0.5f;
            r.x = Clamp01(r.x);
            Dispatch(m, i, ms, p, r, a);
            used = true;
        }
        if (!used) ++ms.unmatched;
        return;
    }

    if (e.midiSize == 0) return;
    if (e.midi[0] >= 0xF0) return;   // clock, start, stop: the tempo's (automation), not a control
    const uint8_t st = e.midi[0], type = st & 0xF0;
    const int ch = (st & 0x0F) + 1;
    const int d1 = e.midiSize > 1 ? (e.midi[1] & 0x7F) : 0;
    const int d2 = e.midiSize > 2 ? (e.midi[2] & 0x7F) : 0;

    // NRPN: CC 99/98 select a parameter, CC 6/38 carry its value (MSB/LSB). RPN (101/100)
    // deselects, so RPN data entry (pitch-bend range and the like) never reaches NRPN maps.
    int nrpnNumber = -1;
    bool nrpnLsb = false;
    int nrpnValue = 0;
    if (type == 0xB0) {
        NrpnChannelState& n = ms.nrpn[ch - 1];
        if (d1 == 99) n.paramMsb = d2;
        else if (d1 == 98) n.paramLsb = d2;
        else if (d1 == 101 || d1 == 100) n.paramMsb = n.paramLsb = -1;
        else if ((d1 == 6 || d1 == 38) && n.paramMsb >= 0 && n.paramLsb >= 0) {
            nrpnNumber = (n.paramMsb << 7) | n.paramLsb;
            if (d1 == 6) {
                n.valueMsb = d2;
                nrpnValue = d2 << 7;
            } else {
                nrpnLsb = true;
                nrpnValue = (n.valueMsb << 7) | d2;
            }
        }
    }

    for (size_t i = 0; i < m.entries.size(); ++i) {
        const MappingEntry& en = m.entries[i];
        if (en.kind == SourceKind::Osc || en.kind == SourceKind::Audio || !ChannelMatches(en, ch)) continue;
        Reading r;
        switch (en.kind) {
            case SourceKind::Cc:
                if (type != 0xB0) continue;
                if (en.hiRes) {
                    EntryState& es = ms.entries[i];
                    if (d1 == en.number) {
                        es.msb = d2;
                        r.x = float(d2 << 7) / 16383.0f;
                    } else if (d1 == en.number + 32 && es.msb >= 0) {
                        r.x = float((es.msb << 7) | d2) / 16383.0f;
                    } else {
                        continue;
                    }
                } else {
                    if (d1 != en.number) continue;
                    if (en.encoder != EncoderMode::Absolute) {
                        r.relative = true;
                        r.ticks = DecodeRelative(en.encoder, d2);
                    }
                    r.x = float(d2) / 127.0f;
                }
                r.pressed = d2 >= 64;
                r.number = d1;
                break;
            case SourceKind::Note:
                if ((type != 0x90 && type != 0x80) || d1 != en.number) continue;
                r.pressed = type == 0x90 && d2 > 0;
                if (en.action == PadAction::None && !r.pressed) continue;  // velocity knob: ignore release
                r.x = float(d2) / 127.0f;
                r.number = d1;
                break;
            case SourceKind::PitchBend:
                if (type != 0xE0) continue;
                r.x = float(d1 | (d2 << 7)) / 16383.0f;
                r.pressed = r.x >= 0.5f;
                break;
            case SourceKind::Program:
                if (type != 0xC0 || (en.number >= 0 && d1 != en.number)) continue;
                r.x = float(d1) / 127.0f;
                r.pressed = true;
                r.number = d1;
                break;
            case SourceKind::Nrpn:
                if (nrpnNumber < 0 || nrpnNumber != en.number) continue;
                if (!en.hiRes && nrpnLsb) continue;
                r.x = en.hiRes ? float(nrpnValue) / 16383.0f : float(nrpnValue >> 7) / 127.0f;
                r.pressed = r.x >= 0.5f;
                r.number = nrpnNumber;
                break;
            case SourceKind::Osc:
            case SourceKind::Audio:
                continue;
        }
        Dispatch(m, i, ms, p, r, a);
        used = true;
    }
    if (!used) ++ms.unmatched;
}

}  // namespace sdfvj
