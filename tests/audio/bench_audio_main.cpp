// audio_bench_tool [seconds]: what the audio analysis costs the render thread per frame (not a
// test; run by hand). Feeds a click train over a bass sine in 800-sample frames (60 fps at
// 48 kHz) and prints the median and 99th-percentile microseconds of Process + TakeFeatures.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "audio/audio.h"
#include "signals.h"

int main(int argc, char** argv) {
    const double seconds = argc > 1 ? std::atof(argv[1]) : 60.0;
    std::vector<float> audio = sdfvj::test::ClickTrain(128.0, seconds);
    const std::vector<float> bass = sdfvj::test::Sine(93.75f, 0.3f, seconds);
    for (size_t i = 0; i < audio.size(); ++i) audio[i] += bass[i];
    sdfvj::AudioAnalyzer an;
    std::vector<double> us;
    for (size_t i = 0; i + 800 <= audio.size(); i += 800) {
        const auto t0 = std::chrono::steady_clock::now();
        an.Process(audio.data() + i, 800);
        an.TakeFeatures();
        us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(us.begin(), us.end());
    std::printf("audio analysis, %zu frames of 800 samples (60 fps at 48 kHz): median %.1f us, p99 %.1f us, "
                "max %.1f us; %llu onsets, %llu beats\n",
                us.size(), us[us.size() / 2], us[us.size() * 99 / 100], us.back(),
                (unsigned long long)an.Onsets(), (unsigned long long)an.Beats());
    return 0;
}
