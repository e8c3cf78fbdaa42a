// `live --forward`: a leader re-sends what its show applies to follower nodes (live_forward.h).
#include "app/live_forward.h"

#include <lo/lo.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "scene/scene.h"

namespace sdfvj {

// Owns the liblo addresses; freed when the last LiveForward copy goes.
struct ForwardTargets {
    std::vector<lo_address> addresses;
    ForwardTargets() = default;
    ForwardTargets(const ForwardTargets&) = delete;
    ForwardTargets& operator=(const ForwardTargets&) = delete;
    ~ForwardTargets() {
        for (lo_address a : addresses) lo_address_free(a);
    }
};

namespace {

bool IsPort(const std::string& s) {
    if (s.empty() || s.size() > 5 || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return false;
    const long n = std::strtol(s.c_str(), nullptr, 10);
    return n >= 1 && n <= 65535;
}

// One message to every follower. UDP: a follower that is not (yet) listening loses it, and the
// next whole state makes up for it.
void SendFloat(LiveForward& f, const std::string& address, float v) {
    for (lo_address a : f.targets->addresses) lo_send(a, address.c_str(), "f", v);
    ++f.sent;
}

void SendPreset(LiveForward& f, const std::string& file, bool state) {
    for (lo_address a : f.targets->addresses) {
        if (state) lo_send(a, "/sdfvj/preset", "ss", file.c_str(), "state");
        else lo_send(a, "/sdfvj/preset", "s", file.c_str());
    }
    ++f.sent;
}

void SendEffect(LiveForward& f, const std::string& name, bool on) {
    for (lo_address a : f.targets->addresses) lo_send(a, ("/sdfvj/effect/" + name).c_str(), "i", on ? 1 : 0);
    ++f.sent;
}

void SendEffects(LiveForward& f, const EffectSet& effects) {
    const std::string list = DescribeEffects(effects);
    for (lo_address a : f.targets->addresses) lo_send(a, "/sdfvj/effects", "s", list.c_str());
    ++f.sent;
}

}  // namespace

bool OpenLiveForward(const std::string& spec, LiveForward* f, std::string* error) {
    *f = LiveForward{};
    if (spec.empty()) return true;
    auto targets = std::make_shared<ForwardTargets>();
    size_t from = 0;
    for (;;) {
        const size_t comma = spec.find(',', from);
        const std::string one = spec.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
        const size_t colon = one.rfind(':');
        if (colon == std::string::npos || colon == 0 || !IsPort(one.substr(colon + 1))) {
            *error = "--forward '" + spec + "': '" + one + "' is not HOST:PORT (port 1..65535), expected HOST:PORT[,HOST:PORT...]";
            return false;
        }
        lo_address a = lo_address_new(one.substr(0, colon).c_str(), one.substr(colon + 1).c_str());
        if (!a) {
            *error = "--forward '" + spec + "': cannot resolve '" + one + "', expected HOST:PORT[,HOST:PORT...]";
            return false;
        }
        targets->addresses.push_back(a);
        f->names.push_back(one);
        if (comma == std::string::npos) break;
        from = comma + 1;
    }
    f->targets = std::move(targets);
    return true;
}

bool IsForwarding(const LiveForward& f) { return f.targets && !f.targets->addresses.empty(); }

void ForwardBeforeControl(LiveForward& f, const LiveState& state) {
    if (!IsForwarding(f)) return;
    f.paramNames.resize(state.params.decls.size());
    for (size_t i = 0; i < state.params.decls.size(); ++i) f.paramNames[i] = state.params.decls[i].name;
    f.before = state.params.target;
    f.presetBefore = state.currentPreset;
}

void ForwardAfterActions(LiveForward& f, const LiveState& state, double now) {
    if (!IsForwarding(f)) return;
    const ParamState& p = state.params;
    // What the mapping moved. The parameters are the same list as before ApplyControl unless
    // something between changed the scene's declarations: then the whole state goes out now.
    bool sameParams = f.before.size() == p.target.size() && f.paramNames.size() == p.decls.size();
    for (size_t i = 0; sameParams && i < p.decls.size(); ++i) sameParams = f.paramNames[i] == p.decls[i].name;
    if (!sameParams) f.lastState = -1e9;
    else
        for (size_t i = 0; i < p.target.size(); ++i)
            if (p.target[i] != f.before[i]) SendFloat(f, "/sdfvj/raw/" + p.decls[i].name, p.target[i]);
    // Preset requests resolved as ApplyActions resolved them ("next" from the preset before it).
    if (!state.actions.presetSelect.empty()) {
        const std::vector<std::string> presets = ListPresets();
        std::string current = f.presetBefore;
        for (const std::string& request : state.actions.presetSelect) {
            const std::string name = ResolvePresetRequest(request, current, presets);
            if (name.empty()) continue;
            SendPreset(f, name, false);
            current = name;
        }
    }
    for (const auto& [name, on] : state.actions.effectToggles) SendEffect(f, name, on);
    // The whole state: the preset first (a follower on another preset applies it, which resets
    // its values), then every target (which a follower on the same preset takes at once).
    if (now - f.lastState < f.stateInterval) return;
    f.lastState = now;
    if (!state.currentPreset.empty()) SendPreset(f, state.currentPreset, true);
    SendEffects(f, state.wanted.effects);   // after the preset, whose own effects it replaces
    for (size_t i = 0; i < p.decls.size(); ++i) SendFloat(f, "/sdfvj/raw/" + p.decls[i].name, p.target[i]);
}

void ForwardFrame(LiveForward& f, const LiveState& state, double show, bool running, float beat, float bpm) {
    if (!IsForwarding(f)) return;
    const double t = std::clamp(show, 0.0, double(kLeaderClockMaxSeconds));
    int32_t seconds = int32_t(std::floor(t));
    int32_t micros = int32_t(std::lround((t - seconds) * 1e6));
    if (micros > 999999) micros = 0, ++seconds;
    const ParamState& p = state.params;
    lo_message m = lo_message_new();
    lo_message_add_int32(m, std::min(seconds, kLeaderClockMaxSeconds));
    lo_message_add_int32(m, micros);
    lo_message_add_int32(m, running ? 1 : 0);
    for (size_t i = 0; i < p.decls.size() && i < 254; ++i) {
        lo_message_add_string(m, p.decls[i].name.c_str());
        lo_message_add_float(m, p.value[i]);
    }
    // The tempo this frame renders with (u_beat, u_bpm): a follower draws the leader's beat, not
    // its own tap or clock. '@' cannot start a parameter name, so no scene input takes these.
    lo_message_add_string(m, kLeaderBeatName);
    lo_message_add_float(m, beat);
    lo_message_add_string(m, kLeaderBpmName);
    lo_message_add_float(m, bpm);
    for (lo_address a : f.targets->addresses) lo_send_message(a, "/sdfvj/clock", m);
    lo_message_free(m);
    ++f.sent;
    ++f.frames;
}

bool IsLeaderClock(const ControlEvent& e) { return e.source == EventSource::Osc && e.address == "/sdfvj/clock"; }

void DropPresetStatesOnStage(std::vector<ControlEvent>* events, const std::string& currentPreset) {
    if (currentPreset.empty()) return;
    std::erase_if(*events, [&](const ControlEvent& e) {
        return e.source == EventSource::Osc && e.address == "/sdfvj/preset" && e.args.size() >= 2 &&
               e.args[0].type == 's' && e.args[1].type == 's' && e.args[1].s == "state" && e.args[0].s == currentPreset;
    });
}

}  // namespace sdfvj
