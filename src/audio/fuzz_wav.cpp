// libFuzzer entry for the WAV reader (`render --replay` reads the take's .wav, which a crash may
// have cut anywhere): any bytes must give audio or one "name: byte N: ..." error, never a crash,
// a sanitizer report or a runaway allocation; and audio it gives must replay (AudioReplay: the
// spectrum and waveform ISF audio inputs read) with finite values. Run with scripts/fuzz.sh --only wav.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "audio/wav.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    sdfvj::WavAudio wav;
    std::string error;
    if (sdfvj::ParseWav(data, size, "fuzz.wav", &wav, &error)) {
        // What AudioReplay relies on: a sample rate in range, samples in -1..1, a finite origin.
        if (wav.sampleRate < 1000 || wav.sampleRate > 384000) std::abort();
        for (float s : wav.samples)
            if (!(s >= -1.0f && s <= 1.0f)) std::abort();
        if (!std::isfinite(wav.origin)) std::abort();
        if (wav.samples.size() > size) std::abort();   // never more samples than bytes
        // The file cut short reads as no more audio than the whole, or fails with an error.
        for (size_t cut : {size - 1, size / 2}) {
            sdfvj::WavAudio part;
            std::string why;
            if (sdfvj::ParseWav(data, cut, "fuzz.wav", &part, &why)) {
                if (part.samples.size() > wav.samples.size()) std::abort();
            } else if (why.rfind("fuzz.wav: byte ", 0) != 0) {
                std::abort();
            }
        }
        // Replayed as `render --replay` does, at times before, inside and past the audio.
        sdfvj::AudioReplay replay(std::move(wav));
        for (double t : {-1.0, 0.0, 0.01, 0.5, 3.0, 1e6}) {
            const sdfvj::AudioSpectrum& s = replay.At(replay.Wav().origin + t);
            for (float v : s.spectrum)
                if (!std::isfinite(v)) std::abort();
            for (float v : s.waveform)
                if (!std::isfinite(v)) std::abort();
        }
    } else if (error.rfind("fuzz.wav: byte ", 0) != 0) {
        std::abort();
    }
    return 0;
}
