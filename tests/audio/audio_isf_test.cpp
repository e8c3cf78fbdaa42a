// The audio input's spectrum and waveform reach ISF `audioFFT` / `audio` inputs (llvmpipe): a
// generator that draws both shows the sine's bin and its wave, within 1/255 per texel.
#include <catch2/catch.hpp>

#include "audio/audio.h"
#include "isf_test_util.h"
#include "signals.h"

using namespace sdfvj;
using namespace sdfvj::isftest;

TEST_CASE("audio isf: audioFFT and audio inputs read the analysis's spectrum and wave", "[audio][gl]") {
    RequireGl();
    AudioAnalyzer an;
    const std::vector<float> sine = test::Sine(21 * 46.875f, 0.5f, 0.2);
    an.Process(sine.data(), sine.size());
    an.TakeFeatures();
    const AudioSpectrum& sp = an.Spectrum();

    IsfEffect e;
    LoadOrFail(e, SDFVJ_AUDIO_TEST_FILES "/audio_view.fs");
    IsfFrameInputs in;
    in.audioWaveform = sp.waveform;
    in.audioSpectrum = sp.spectrum;
    Img img = ReadBack(e.Render(0, kAudioBins, 2, in), kAudioBins, 2);
    int peak = 0;
    for (int x = 0; x < kAudioBins; ++x) {
        INFO("x " << x);
        REQUIRE(std::abs(img.At(x, 0, 0) - int(std::lround(sp.spectrum[size_t(x)] * 255))) <= 1);
        REQUIRE(std::abs(img.At(x, 0, 1) - int(std::lround((0.5f + 0.5f * sp.waveform[size_t(x)]) * 255))) <= 1);
        if (img.At(x, 0, 0) > img.At(peak, 0, 0)) peak = x;
    }
    CHECK(peak == 21);   // the sine's bin is the brightest column
    Save("audio_view", img);

    // No audio: the silent textures (spectrum 0, wave at rest 0.5).
    Img quiet = ReadBack(e.Render(0, kAudioBins, 2, IsfFrameInputs{}), kAudioBins, 2);
    for (int x = 0; x < kAudioBins; x += 37) {
        CHECK(quiet.At(x, 1, 0) == 0);
        CHECK(std::abs(quiet.At(x, 1, 1) - 128) <= 1);
    }
}
