// Synthetic test signals for the audio tests: sines, click trains, silence. Deterministic (no
// random device), so a failing test fails the same way every run.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

namespace sdfvj::test {

inline std::vector<float> Sine(float hz, float amplitude, double seconds, int rate = 48000) {
    std::vector<float> s(size_t(seconds * rate));
    for (size_t i = 0; i < s.size(); ++i) s[i] = amplitude * float(std::sin(2.0 * M_PI * hz * double(i) / rate));
    return s;
}

// A drum-like click every 60/bpm seconds: 30 ms of decaying noise plus a 60 Hz thump.
inline std::vector<float> ClickTrain(double bpm, double seconds, int rate = 48000, float amplitude = 0.8f) {
    std::vector<float> s(size_t(seconds * rate), 0.0f);
    const double period = 60.0 / bpm;
    uint32_t lcg = 12345;
    for (double t = 0.05; t < seconds; t += period) {
        const size_t start = size_t(t * rate);
        for (size_t i = 0; i < size_t(0.03 * rate) && start + i < s.size(); ++i) {
            lcg = lcg * 1664525u + 1013904223u;
            const float noise = float(int32_t(lcg >> 8) - (1 << 23)) / float(1 << 23);
            const float env = std::exp(-float(i) / (0.006f * rate));
            const float thump = std::sin(2.0f * float(M_PI) * 60.0f * float(i) / rate);
            s[start + i] = amplitude * env * (0.6f * noise + 0.4f * thump);
        }
    }
    return s;
}

}  // namespace sdfvj::test
