// Writes presets/demo_take.mid: an 8-second take for the `midi` scene, reproducibly.
//
// Channel 1, CC 1..4 = knobs 1..4 of the shipped controller profiles (scale, twist,
// displacement, smoothness), sent like a real controller: only when the 7-bit value changes,
// at most every 10 ms. Four notes (pads) mark the beats at 1, 3, 5 and 7 s.
//   usage: sdfvj_make_demo_take [out.mid]   (default: presets/demo_take.mid of the source tree)
#include <cmath>
#include <cstdio>

#include "take/take.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kLength = 8.0;

// Knob curves over t in [0, kLength], 0..1.
double Scale(double t) { return 0.5 + 0.35 * std::sin(2.0 * kPi * t / kLength); }
double Twist(double t) { return t < 4.0 ? t / 4.0 : (8.0 - t) / 4.0; }                // up, then down
double Displacement(double t) { return 0.5 * (1.0 - std::cos(2.0 * kPi * t / 2.0)) * (t / kLength); }
double Smoothness(double t) { return 0.2 + 0.6 * (0.5 - 0.5 * std::cos(kPi * t / kLength)); }

sdfvj::ControlEvent Midi(double t, uint8_t status, uint8_t a, uint8_t b) {
    sdfvj::ControlEvent e;
    e.time = t;
    e.source = sdfvj::EventSource::Midi;
    e.midi[0] = status;
    e.midi[1] = a;
    e.midi[2] = b;
    e.midiSize = 3;
    return e;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string path = argc > 1 ? argv[1] : std::string(SDFVJ_SOURCE_ROOT) + "/presets/demo_take.mid";
    double (*curves[4])(double) = {Scale, Twist, Displacement, Smoothness};
    int last[4] = {-1, -1, -1, -1};
    sdfvj::Take take;
    for (int ms = 0; ms <= int(kLength * 1000); ms += 10) {
        const double t = ms / 1000.0;
        for (int k = 0; k < 4; ++k) {
            const int v = int(std::lround(127.0 * std::fmin(1.0, std::fmax(0.0, curves[k](t)))));
            if (v == last[k]) continue;
            last[k] = v;
            take.events.push_back(Midi(t, 0xB0, uint8_t(1 + k), uint8_t(v)));
        }
        if (ms % 2000 == 1000) take.events.push_back(Midi(t, 0x90, uint8_t(36 + (ms / 2000) * 2), 100));
        if (ms % 2000 == 1250) take.events.push_back(Midi(t, 0x80, uint8_t(36 + (ms / 2000) * 2), 0));
    }
    take.duration = kLength;
    std::string error;
    if (!sdfvj::WriteTake(path, take, &error)) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
    }
    std::printf("%s: %zu events, %.1f s\n", path.c_str(), take.events.size(), take.duration);
    return 0;
}
