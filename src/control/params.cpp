// ParamState: clamped targets and deterministic one-pole smoothing.
#include <cmath>
#include <cstdio>

#include "control/control.h"

namespace sdfvj {

std::string ParamNameList(const std::vector<ParamDecl>& decls) {
    std::string s;
    for (const ParamDecl& d : decls) s += (s.empty() ? "" : ", ") + d.name;
    return s.empty() ? "(none)" : s;
}

ParamState MakeParamState(const std::vector<ParamDecl>& decls) {
    ParamState s;
    s.decls = decls;
    for (const ParamDecl& d : decls) {
        float v = ClampParam(d, d.defaultValue);
        s.value.push_back(v);
        s.target.push_back(v);
        s.smoothingTau.push_back(d.type == ParamType::Float ? 0.05f : 0.0f);
    }
    return s;
}

int FindParam(const ParamState& s, const std::string& name) {
    for (size_t i = 0; i < s.decls.size(); ++i)
        if (s.decls[i].name == name) return int(i);
    return -1;
}

bool SetParamTarget(ParamState& s, int i, float v) {
    if (i < 0 || i >= int(s.decls.size())) return false;
    float c = ClampParam(s.decls[i], v);
    s.target[i] = c;
    bool rounded = s.decls[i].type != ParamType::Float;
    if (c != v && !(rounded && std::isfinite(v) && v >= s.decls[i].minValue && v <= s.decls[i].maxValue)) {
        ++s.clamped;
        char buf[256];
        std::snprintf(buf, sizeof buf, "%s: %g is outside [%g, %g], clamped to %g",
                      s.decls[i].name.c_str(), double(v), double(s.decls[i].minValue),
                      double(s.decls[i].maxValue), double(c));
        s.lastClamp = buf;
        return false;
    }
    return true;
}

bool SetParamByName(ParamState& s, const std::string& name, float v, std::string* error) {
    int i = FindParam(s, name);
    if (i < 0) {
        if (error) *error = "unknown parameter '" + name + "', expected one of: " + ParamNameList(s.decls);
        return false;
    }
    if (!std::isfinite(v)) {
        if (error) *error = name + ": value is not a finite number, ignored";
        return false;
    }
    if (!SetParamTarget(s, i, v)) {
        if (error) *error = s.lastClamp;
        return false;
    }
    return true;
}

void StepSmoothing(ParamState& s, double dt) {
    for (size_t i = 0; i < s.value.size(); ++i) {
        float tau = s.smoothingTau[i];
        if (tau <= 0.0f || dt <= 0.0 || s.decls[i].type != ParamType::Float) {
            if (dt > 0.0 || tau <= 0.0f) s.value[i] = s.target[i];
            continue;
        }
        float a = float(1.0 - std::exp(-dt / double(tau)));
        float v = s.value[i] + (s.target[i] - s.value[i]) * a;
        // Snap the tail so a value settles exactly instead of creeping forever.
        float range = std::fabs(s.decls[i].maxValue - s.decls[i].minValue);
        if (std::fabs(s.target[i] - v) <= 1e-5f * (range > 0.0f ? range : 1.0f)) v = s.target[i];
        s.value[i] = v;
    }
}

}  // namespace sdfvj
