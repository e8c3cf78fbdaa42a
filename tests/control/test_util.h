// Shared bits for the input-layer tests: the `midi` scene's parameters and a wait helper.
#pragma once
#include <chrono>
#include <functional>
#include <thread>

#include "control/control.h"

namespace sdfvj::test {

// The four parameters of the `midi` scene (the design card's), plus a bool for pads.
inline std::vector<ParamDecl> MidiSceneDecls() {
    return {
        {"scale", ParamType::Float, 1.0f, 0.5f, 2.0f, "Scale"},
        {"twist", ParamType::Float, 0.0f, -3.0f, 3.0f, "Twist"},
        {"displacement", ParamType::Float, 0.0f, 0.0f, 1.0f, "Displacement"},
        {"smoothness", ParamType::Float, 0.1f, 0.0f, 0.5f, "Smoothness"},
        {"flag", ParamType::Bool, 0.0f, 0.0f, 1.0f, "Flag"},
    };
}

inline double Now() {
    static const auto t0 = std::chrono::steady_clock::now();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Polls `done` every millisecond until it is true or `seconds` pass.
inline bool WaitFor(const std::function<bool()>& done, double seconds) {
    double end = Now() + seconds;
    while (Now() < end) {
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return done();
}

inline float Param(const ParamState& s, const char* name) { return s.target[FindParam(s, name)]; }

}  // namespace sdfvj::test
