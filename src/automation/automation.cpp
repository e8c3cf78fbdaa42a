// Scripted presets: muparser expressions, LFOs, envelopes, cues, tempo and morphs.
#include "automation/automation.h"

#include <muParser.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <map>
#include <set>

namespace sdfvj {

namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr int kKnobs = 16;

double Fract(double x) { return x - std::floor(x); }
double LfoSine(double x) { return std::sin(kTwoPi * x); }
double LfoTri(double x) { double f = Fract(x); return f < 0.5 ? 4.0 * f - 1.0 : 3.0 - 4.0 * f; }
double LfoSaw(double x) { return 2.0 * Fract(x) - 1.0; }
double LfoSquare(double x) { return Fract(x) < 0.5 ? 1.0 : -1.0; }
// Random and hold: one value per whole cycle, the same on every run (a hash of the cycle index).
double LfoRand(double x) {
    if (!std::isfinite(x)) return 0.0;
    uint64_t h = (uint64_t)(int64_t)std::floor(x) * 0x9E3779B97F4A7C15ull;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return (double)(h >> 11) / (double)(1ull << 53) * 2.0 - 1.0;
}
double Clamp(double x, double a, double b) { return std::min(std::max(x, std::min(a, b)), std::max(a, b)); }
double Mix(double a, double b, double t) { return a + (b - a) * t; }
double SmoothStep(double a, double b, double x) {
    if (a == b) return x < a ? 0.0 : 1.0;
    double t = Clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}
double Step(double edge, double x) { return x < edge ? 0.0 : 1.0; }
double EaseFn(double t) { t = Clamp(t, 0.0, 1.0); return t * t * (3.0 - 2.0 * t); }

bool IsIdentifier(const std::string& s) {
    if (s.empty() || std::isdigit((unsigned char)s[0])) return false;
    return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum((unsigned char)c) || c == '_'; });
}

struct EnvelopeState {
    EnvelopeDesc desc;
    double onTime = -1.0;          // < 0: never fired
    double offTime = -1.0;         // < 0: held
    double levelAtOff = 0.0;
    double Level(double t) const {
        if (onTime < 0.0 || t < onTime) return 0.0;
        auto held = [&](double u) {
            const double dt = u - onTime;
            if (dt < desc.attack) return desc.attack > 0.0 ? dt / desc.attack : 1.0;
            if (dt < desc.attack + desc.decay) return 1.0 - (1.0 - desc.sustain) * (dt - desc.attack) / desc.decay;
            return desc.sustain;
        };
        if (offTime < 0.0 || t < offTime) return held(t);
        if (desc.release <= 0.0) return 0.0;
        return std::max(0.0, levelAtOff * (1.0 - (t - offTime) / desc.release));
    }
};

}  // namespace

struct Automation::Impl {
    AutomationDesc desc;
    // Variables live at fixed addresses (muparser binds pointers): a deque never moves them.
    std::deque<double> storage;
    double* time = nullptr;
    double* frame = nullptr;
    double* beat = nullptr;
    double* bar = nullptr;
    double* bpm = nullptr;
    std::vector<double*> knobs;
    std::map<std::string, double*> paramVars;     // scene parameter -> variable
    std::map<std::string, double*> envelopeVars;  // envelope name -> env_<name>
    std::map<std::string, EnvelopeState> envelopes;
    struct Compiled {
        ExpressionDesc desc;
        std::unique_ptr<mu::Parser> parser;
        bool reported = false;
    };
    std::vector<Compiled> expressions;
    double startBeats = 0.0;
    double lastLocal = -1e300;
    bool started = false;

    double* NewVar() {
        storage.push_back(0.0);
        return &storage.back();
    }
    void Define(mu::Parser& p) {
        p.DefineFun("lfo_sine", LfoSine);
        p.DefineFun("lfo_tri", LfoTri);
        p.DefineFun("lfo_saw", LfoSaw);
        p.DefineFun("lfo_square", LfoSquare);
        p.DefineFun("lfo_rand", LfoRand, false);
        p.DefineFun("fract", Fract);
        p.DefineFun("clamp", Clamp);
        p.DefineFun("mix", Mix);
        p.DefineFun("smoothstep", SmoothStep);
        p.DefineFun("step", Step);
        p.DefineFun("ease", EaseFn);
        p.DefineVar("time", time);
        p.DefineVar("frame", frame);
        p.DefineVar("beat", beat);
        p.DefineVar("bar", bar);
        p.DefineVar("bpm", bpm);
        for (int i = 0; i < kKnobs; ++i) p.DefineVar("knob" + std::to_string(i + 1), knobs[(size_t)i]);
        for (auto& [name, var] : envelopeVars) p.DefineVar("env_" + name, var);
        for (auto& [name, var] : paramVars) p.DefineVar(name, var);
    }
};

void TempoState::SetBpm(double now, double newBpm) {
    if (!std::isfinite(newBpm)) return;
    originBeats = Beats(now);
    originTime = now;
    bpm = std::clamp(newBpm, 20.0, 400.0);
}

void TempoState::TapOnBeat(double now, double newBpm) {
    SetBpm(now, newBpm);
    originBeats = std::round(originBeats);
}

void TapTempo::Tap(double now) {
    if (!taps.empty() && now - taps.back() > 2.0) taps.clear();   // a pause starts a new count
    taps.push_back(now);
    if (taps.size() > 5) taps.erase(taps.begin());
    if (taps.size() >= 2) {
        std::vector<double> gaps;
        for (size_t i = 1; i < taps.size(); ++i) gaps.push_back(taps[i] - taps[i - 1]);
        std::sort(gaps.begin(), gaps.end());
        double gap = gaps[gaps.size() / 2];
        if (gap > 0.2 && gap < 2.0) bpm = 60.0 / gap;
    }
    origin = now;
}

float TapTempo::Phase(double now) const {
    double beats = (now - origin) * bpm / 60.0;
    return (float)(beats - std::floor(beats));
}

bool MidiClockFollower::OnEvent(const ControlEvent& e, TempoState& tempo) {
    if (e.source != EventSource::Midi || e.midiSize < 1) return false;
    const uint8_t status = e.midi[0];
    if (status == 0xF8) {
        seen = true;
        pulses.push_back(e.time);
        if (pulses.size() > 25) pulses.erase(pulses.begin());
        if (pulses.size() >= 7) {
            std::vector<double> gaps;
            for (size_t i = 1; i < pulses.size(); ++i) gaps.push_back(pulses[i] - pulses[i - 1]);
            std::sort(gaps.begin(), gaps.end());
            const double gap = gaps[gaps.size() / 2];
            if (gap > 1e-4) tempo.SetBpm(e.time, 60.0 / (gap * 24.0));
        }
        return true;
    }
    if (status == 0xFA) {   // start: beat 0 now
        seen = true;
        pulses.clear();
        tempo.originTime = e.time;
        tempo.originBeats = 0.0;
        tempo.running = true;
        return true;
    }
    if (status == 0xFB) {   // continue
        tempo.originTime = e.time;
        tempo.running = true;
        return true;
    }
    if (status == 0xFC) {   // stop: hold the beat where it is
        tempo.originBeats = tempo.Beats(e.time);
        tempo.originTime = e.time;
        tempo.running = false;
        return true;
    }
    return false;
}

Automation::Automation() : impl_(std::make_unique<Impl>()) {}
Automation::~Automation() = default;
Automation::Automation(Automation&&) noexcept = default;
Automation& Automation::operator=(Automation&&) noexcept = default;

void Automation::Clear() { impl_ = std::make_unique<Impl>(); }

bool Automation::Load(const AutomationDesc& desc, const std::vector<ParamDecl>& decls, std::string* error) {
    auto next = std::make_unique<Impl>();
    Impl& a = *next;
    a.desc = desc;
    const std::string file = desc.file.empty() ? "<preset>" : desc.file;
    auto fail = [&](int line, const std::string& what) {
        *error = file + ":" + std::to_string(std::max(line, 1)) + ": " + what;
        return false;
    };
    a.time = a.NewVar();
    a.frame = a.NewVar();
    a.beat = a.NewVar();
    a.bar = a.NewVar();
    a.bpm = a.NewVar();
    for (int i = 0; i < kKnobs; ++i) a.knobs.push_back(a.NewVar());
    static const std::set<std::string> kReserved = {"time", "frame", "beat", "bar", "bpm"};
    for (const ParamDecl& d : decls)
        if (!kReserved.count(d.name) && d.name.rfind("knob", 0) != 0 && d.name.rfind("env_", 0) != 0)
            a.paramVars[d.name] = a.NewVar();
    for (const EnvelopeDesc& e : desc.envelopes) {
        if (!IsIdentifier(e.name)) return fail(e.line, "envelope name '" + e.name + "' is not an identifier, expected letters, digits and _");
        if (a.envelopes.count(e.name)) return fail(e.line, "envelope '" + e.name + "' is declared twice, expected unique names");
        if (!(e.attack >= 0 && e.decay >= 0 && e.release >= 0 && e.sustain >= 0 && e.sustain <= 1 && e.attack < 3600 &&
              e.decay < 3600 && e.release < 3600))
            return fail(e.line, "envelope '" + e.name + "' has a bad time or level, expected attack, decay, release >= 0 s and sustain 0..1");
        a.envelopes[e.name].desc = e;
        a.envelopeVars[e.name] = a.NewVar();
    }
    for (const ExpressionDesc& x : desc.expressions) {
        auto decl = std::find_if(decls.begin(), decls.end(), [&](const ParamDecl& d) { return d.name == x.param; });
        if (decl == decls.end())
            return fail(x.line, "expression for '" + x.param + "', which the scene does not declare, expected one of: " +
                                    ParamNameList(decls));
        Impl::Compiled c;
        c.desc = x;
        c.parser = std::make_unique<mu::Parser>();
        try {
            a.Define(*c.parser);
            c.parser->SetExpr(x.text);
            c.parser->Eval();   // parses now: unknown names and syntax errors are reported at load
        } catch (const mu::Parser::exception_type& e) {
            return fail(x.line, "expression for '" + x.param + "' does not parse: " + e.GetMsg() + " (at column " +
                                    std::to_string(e.GetPos() + 1) + " of \"" + x.text.substr(0, 200) +
                                    "\"), expected arithmetic on time, beat, bar, bpm, frame, knobN, env_NAME, "
                                    "parameters and lfo_sine/lfo_tri/lfo_saw/lfo_square/lfo_rand");
        } catch (const std::exception& e) {
            return fail(x.line, "expression for '" + x.param + "' does not parse: " + e.what());
        }
        a.expressions.push_back(std::move(c));
    }
    for (const CueDesc& c : desc.cues)
        if (!(c.bar >= 0 && c.bar < 1e6 && c.overBeats >= 0 && c.overBeats < 1e4))
            return fail(c.line, "cue at bar " + std::to_string(c.bar) + " is out of range, expected bar >= 0 and over >= 0 beats");
    if (!(desc.loopBars >= 0 && desc.loopBars < 1e6)) return fail(1, "loop_bars is out of range, expected a bar count >= 0");
    impl_ = std::move(next);
    return true;
}

void Automation::Start(double beats) {
    impl_->startBeats = beats;
    impl_->lastLocal = -1e300;
    impl_->started = true;
}

void Automation::OnEvent(const ControlEvent& e) {
    Impl& a = *impl_;
    if (a.envelopes.empty()) return;
    if (e.source == EventSource::Midi && e.midiSize >= 3) {
        const uint8_t type = e.midi[0] & 0xF0;
        const int channel = (e.midi[0] & 0x0F) + 1;
        if (type != 0x90 && type != 0x80) return;
        const bool on = type == 0x90 && e.midi[2] > 0;
        for (auto& [name, env] : a.envelopes)
            if (env.desc.note == e.midi[1] && (env.desc.channel == 0 || env.desc.channel == channel)) Fire(name, on, e.time);
        return;
    }
    if (e.source == EventSource::Osc && e.address.rfind("/sdfvj/env/", 0) == 0 && e.args.size() == 1) {
        const OscArg& arg = e.args[0];
        bool on = true;
        if (arg.type == 'i') on = arg.i != 0;
        else if (arg.type == 'f') on = arg.f >= 0.5f;
        else return;
        Fire(e.address.substr(11), on, e.time);
    }
}

void Automation::Fire(const std::string& envelope, bool on, double time) {
    auto it = impl_->envelopes.find(envelope);
    if (it == impl_->envelopes.end()) return;
    EnvelopeState& s = it->second;
    if (on) {
        s.onTime = time;
        s.offTime = -1.0;
    } else if (s.onTime >= 0.0 && s.offTime < 0.0) {
        s.levelAtOff = s.Level(time);
        s.offTime = time;
    }
}

double Automation::EnvelopeValue(const std::string& envelope, double now) const {
    auto it = impl_->envelopes.find(envelope);
    return it == impl_->envelopes.end() ? 0.0 : it->second.Level(now);
}

void Automation::Apply(const AutomationFrame& f, const std::vector<float>& knobs, ParamState& params,
                       std::vector<std::string>* reports) {
    Impl& a = *impl_;
    if (a.expressions.empty()) return;
    *a.time = f.time;
    *a.frame = f.frame;
    *a.beat = f.beats;
    *a.bar = f.beats / 4.0;
    *a.bpm = f.bpm;
    for (int i = 0; i < kKnobs; ++i) *a.knobs[(size_t)i] = i < (int)knobs.size() ? knobs[(size_t)i] : 0.0;
    for (auto& [name, var] : a.envelopeVars) *var = a.envelopes[name].Level(f.time);
    for (auto& [name, var] : a.paramVars) {
        const int i = FindParam(params, name);
        *var = i >= 0 ? params.value[(size_t)i] : 0.0;
    }
    for (Impl::Compiled& c : a.expressions) {
        const int i = FindParam(params, c.desc.param);
        if (i < 0) continue;   // the scene on screen is not this preset's (yet)
        double v = 0.0;
        std::string problem;
        try {
            v = c.parser->Eval();
        } catch (const mu::Parser::exception_type& e) {
            problem = e.GetMsg();
        }
        const ParamDecl& d = params.decls[(size_t)i];
        if (problem.empty() && !std::isfinite(v)) problem = std::isnan(v) ? "gave NaN" : "gave an infinity (a division by zero?)";
        float value = problem.empty() ? (float)v : NAN;
        if (problem.empty() && !std::isfinite(value)) problem = "gave a number too large for a float";
        const float clamped = ClampParam(d, value);
        if (problem.empty() && (double)clamped != v && d.type == ParamType::Float && (v < d.minValue || v > d.maxValue))
            problem = "gave " + std::to_string(v) + ", outside [" + std::to_string(d.minValue) + ", " + std::to_string(d.maxValue) + "]";
        if (!problem.empty() && !c.reported && reports) {
            c.reported = true;
            reports->push_back(a.desc.file + ":" + std::to_string(std::max(c.desc.line, 1)) + ": expression for '" +
                               d.name + "' " + problem + " at time " + std::to_string(f.time) + " s, clamped to " +
                               std::to_string(clamped) + " (reported once), expected a finite value in its range");
        }
        params.target[(size_t)i] = clamped;
        params.value[(size_t)i] = clamped;
    }
}

std::vector<CueDesc> Automation::DueCues(double beats) {
    Impl& a = *impl_;
    std::vector<CueDesc> due;
    if (a.desc.cues.empty() || !a.started) return due;
    double local = beats - a.startBeats;
    const double loop = a.desc.loopBars * 4.0;
    double last = a.lastLocal;
    a.lastLocal = local;
    if (local < last) return due;   // the clock went back (a MIDI start): wait for it
    for (const CueDesc& c : a.desc.cues) {
        const double at = c.bar * 4.0;
        if (loop > 0.0) {
            // Every repeat of this cue in (last, local].
            if (at >= loop) continue;
            const double firstCycle = std::max(0.0, std::floor((std::max(last, 0.0) - at) / loop));
            for (double k = firstCycle; at + k * loop <= local; k += 1.0)
                if (at + k * loop > last) due.push_back(c);
        } else if (at > last && at <= local) {
            due.push_back(c);
        }
    }
    return due;
}

const AutomationDesc& Automation::Desc() const { return impl_->desc; }

bool Automation::Scripted(const std::string& param) const {
    for (const auto& c : impl_->expressions)
        if (c.desc.param == param) return true;
    return false;
}

std::string Automation::ExpressionText(const std::string& param) const {
    for (const auto& c : impl_->expressions)
        if (c.desc.param == param) return c.desc.text;
    return "";
}

std::vector<float> KnobPositions(const Mapping& m, const MappingState& ms) {
    std::vector<float> knobs;
    for (size_t i = 0; i < m.entries.size(); ++i) {
        const MappingEntry& e = m.entries[i];
        if (e.action != PadAction::None || e.kind == SourceKind::Osc || e.kind == SourceKind::Audio) continue;
        const float p = i < ms.entries.size() ? ms.entries[i].position : -1.0f;
        knobs.push_back(p < 0.0f ? 0.0f : p);
    }
    return knobs;
}

float Ease(Easing e, double t) {
    t = std::clamp(t, 0.0, 1.0);
    switch (e) {
        case Easing::Linear: return (float)t;
        case Easing::Smooth: return (float)(t * t * (3.0 - 2.0 * t));
        case Easing::EaseIn: return (float)(t * t * t);
        case Easing::EaseOut: { double u = 1.0 - t; return (float)(1.0 - u * u * u); }
        case Easing::Cut: return 1.0f;
    }
    return (float)t;
}

void StartMorph(ParamMorph& morph, ParamState& params, const std::vector<std::pair<std::string, float>>& values,
                double now, const MorphDesc& how) {
    morph.tracks.clear();
    morph.start = now;
    morph.seconds = how.seconds;
    morph.easing = how.easing;
    for (const auto& [name, v] : values) {
        const int i = FindParam(params, name);
        if (i < 0) continue;
        const float to = ClampParam(params.decls[(size_t)i], v);
        if (how.seconds <= 0.0 || how.easing == Easing::Cut) {
            params.target[(size_t)i] = params.value[(size_t)i] = to;
            continue;
        }
        morph.tracks.push_back({name, params.value[(size_t)i], to});
    }
}

void StepMorph(ParamMorph& morph, ParamState& params, double now, const Automation* automation) {
    if (!morph.Active()) return;
    const double t = morph.seconds > 0.0 ? (now - morph.start) / morph.seconds : 1.0;
    const float k = Ease(morph.easing, t);
    for (const ParamMorph::Track& tr : morph.tracks) {
        const int i = FindParam(params, tr.name);
        if (i < 0 || (automation && automation->Scripted(tr.name))) continue;
        const float v = ClampParam(params.decls[(size_t)i], tr.from + (tr.to - tr.from) * k);
        params.target[(size_t)i] = params.value[(size_t)i] = v;
    }
    if (t >= 1.0) morph.tracks.clear();
}

void FeedAutomation(ShowAutomation& a, const std::vector<ControlEvent>& events) {
    for (const ControlEvent& e : events) {
        if (a.clock.OnEvent(e, a.tempo)) continue;
        a.automation.OnEvent(e);
    }
}

std::vector<CueDesc> StepAutomation(ShowAutomation& a, ParamState& params, const std::vector<float>& knobs, double now,
                                    int frame, std::vector<std::string>* reports) {
    const double beats = a.tempo.Beats(now);
    std::vector<CueDesc> presets;
    for (CueDesc& cue : a.automation.DueCues(beats)) {
        if (!cue.preset.empty()) {
            presets.push_back(std::move(cue));
            continue;
        }
        MorphDesc how = a.automation.Desc().morph;
        how.seconds = cue.overBeats * 60.0 / a.tempo.bpm;
        std::vector<std::pair<std::string, float>> values(cue.values.begin(), cue.values.end());
        StartMorph(a.morph, params, values, now, how);
    }
    AutomationFrame f;
    f.time = now;
    f.frame = frame;
    f.beats = beats;
    f.bpm = a.tempo.bpm;
    a.automation.Apply(f, knobs, params, reports);
    StepMorph(a.morph, params, now, &a.automation);
    return presets;
}

}  // namespace sdfvj
