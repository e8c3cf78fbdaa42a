// AudioAnalyzer on synthetic buffers (no JACK): a sine lands in its bin and band, a click train
// at 128 BPM gives ~128 BPM and one onset per click, silence stays silent.
#include <catch2/catch.hpp>

#include "audio/audio.h"
#include "signals.h"

using namespace sdfvj;

namespace {
// Feeds `s` in 800-sample blocks (a 60 fps frame at 48 kHz) and returns the last features,
// with onset/beat true when any block had one.
AudioFeatures Feed(AudioAnalyzer& a, const std::vector<float>& s, int* onsetFrames = nullptr) {
    AudioFeatures last;
    bool onset = false, beat = false;
    for (size_t i = 0; i < s.size(); i += 800) {
        a.Process(s.data() + i, std::min<size_t>(800, s.size() - i));
        last = a.TakeFeatures();
        onset = onset || last.onset;
        beat = beat || last.beat;
        if (onsetFrames && last.onset) ++*onsetFrames;
    }
    last.onset = onset;
    last.beat = beat;
    return last;
}
}  // namespace

TEST_CASE("audio analysis: a sine peaks in its own bin and band", "[audio]") {
    struct Case { float hz; int bin; const char* band; };
    // Bin k is k * 48000 / 1024 = k * 46.875 Hz.
    for (Case c : {Case{984.375f, 21, "mid"}, Case{93.75f, 2, "bass"}, Case{8015.625f, 171, "high"},
                   Case{140.625f, 3, "bass"}, Case{2015.625f, 43, "mid"}}) {
        INFO(c.hz << " Hz");
        AudioAnalyzer a;
        AudioFeatures f = Feed(a, test::Sine(c.hz, 0.5f, 0.5));
        CHECK(a.BinHz() == Approx(46.875f));
        CHECK(PeakBin(a.Spectrum().spectrum) == c.bin);
        // Amplitude 0.5 = -6 dBFS: spectrum -80..0 dB -> 0..1 reads (80 - 6) / 80 within 1 dB.
        CHECK(a.Spectrum().spectrum[size_t(c.bin)] == Approx(74.0f / 80.0f).margin(1.0f / 80.0f));
        // The band holding the sine reads -6 dBFS ((60 - 6) / 60 within 1 dB); the others are
        // at least 40 dB lower (Hann's leakage).
        const float in = std::string(c.band) == "bass" ? f.bass : std::string(c.band) == "mid" ? f.mid : f.high;
        CHECK(in == Approx(54.0f / 60.0f).margin(1.0f / 60.0f));
        for (float other : {f.bass, f.mid, f.high})
            if (other != in) CHECK(other < in - 40.0f / 60.0f);
        // RMS of a 0.5 sine: -9 dBFS.
        CHECK(f.levelDb == Approx(-9.03f).margin(0.3f));
        // The waveform is the last 512 samples as they were.
        const std::vector<float>& w = a.Spectrum().waveform;
        REQUIRE(w.size() == size_t(kAudioBins));
        CHECK(*std::max_element(w.begin(), w.end()) == Approx(0.5f).margin(0.02f));
        CHECK(*std::min_element(w.begin(), w.end()) == Approx(-0.5f).margin(0.02f));
    }
}

TEST_CASE("audio analysis: the spectrum moves with the sine", "[audio]") {
    AudioAnalyzer a;
    Feed(a, test::Sine(468.75f, 0.5f, 0.3));
    CHECK(PeakBin(a.Spectrum().spectrum) == 10);
    Feed(a, test::Sine(4687.5f, 0.5f, 0.3));
    CHECK(PeakBin(a.Spectrum().spectrum) == 100);
    CHECK(a.Spectrum().spectrum[10] < 0.2f);   // the old peak is gone (below -64 dBFS)
}

TEST_CASE("audio analysis: an onset train at 128 BPM yields 128 BPM", "[audio]") {
    AudioAnalyzer a;
    int onsetFrames = 0;
    const double seconds = 20.0;
    AudioFeatures f = Feed(a, test::ClickTrain(128.0, seconds), &onsetFrames);
    const int clicks = int((seconds - 0.05) * 128.0 / 60.0) + 1;   // 43
    CHECK(f.bpm == Approx(128.0f).margin(2.0f));
    // One onset per click (a click can straddle two frames: allow a few extra or missed).
    CHECK(std::abs(onsetFrames - clicks) <= 3);
    CHECK(a.Beats() >= uint64_t(clicks / 2));
    CHECK(f.beatPhase >= 0.0f);
    CHECK(f.beatPhase < 1.0f);
}

TEST_CASE("audio analysis: a train at 90 BPM is not called 128", "[audio]") {
    AudioAnalyzer a;
    AudioFeatures f = Feed(a, test::ClickTrain(90.0, 20.0));
    CHECK(f.bpm == Approx(90.0f).margin(2.0f));
}

TEST_CASE("audio analysis: silence is silence", "[audio]") {
    AudioAnalyzer a;
    int onsetFrames = 0;
    AudioFeatures f = Feed(a, std::vector<float>(48000 * 5, 0.0f), &onsetFrames);
    CHECK(onsetFrames == 0);
    CHECK_FALSE(f.beat);
    CHECK(a.Beats() == 0);
    CHECK(f.bpm == 0.0f);
    CHECK(f.level == 0.0f);
    CHECK(f.levelDb == -120.0f);
    CHECK(f.bass == 0.0f);
    CHECK(f.mid == 0.0f);
    CHECK(f.high == 0.0f);
    for (float v : a.Spectrum().spectrum) REQUIRE(v == 0.0f);
    // Non-finite samples read as silence, not NaN features.
    std::vector<float> bad(4800, std::nanf(""));
    a.Process(bad.data(), bad.size());
    f = a.TakeFeatures();
    CHECK(f.level == 0.0f);
    CHECK(std::isfinite(f.beatPhase));
}

TEST_CASE("audio analysis: features survive the event round trip bit for bit", "[audio]") {
    AudioAnalyzer a;
    Feed(a, test::ClickTrain(128.0, 6.0));
    AudioFeatures f = a.TakeFeatures();
    f.onset = true;
    ControlEvent e = AudioFeatureEvent(f, 1.5);
    AudioFeatures g;
    REQUIRE(ReadAudioFeatureEvent(e, &g));
    CHECK(e.time == 1.5);
    CHECK(g.level == f.level);
    CHECK(g.bass == f.bass);
    CHECK(g.bpm == f.bpm);
    CHECK(g.beatPhase == f.beatPhase);
    CHECK(g.onset);
    ControlEvent other = e;
    other.address = "/sdfvj/audiox";
    CHECK_FALSE(ReadAudioFeatureEvent(other, &g));
    other = e;
    other.args.resize(3);
    CHECK_FALSE(ReadAudioFeatureEvent(other, &g));
}

TEST_CASE("audio analysis: beats stop a second after the music does", "[audio]") {
    AudioAnalyzer a;
    Feed(a, test::ClickTrain(128.0, 10.0));
    const uint64_t during = a.Beats();
    Feed(a, std::vector<float>(48000, 0.0f));            // aubio may still place one or two
    const uint64_t afterOne = a.Beats();
    Feed(a, std::vector<float>(48000 * 3, 0.0f));
    CHECK(during >= 10);
    CHECK(a.Beats() == afterOne);
}
