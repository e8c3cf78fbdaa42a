// audio: sound in, a few numbers per frame out (level, bands, onsets, tempo, spectrum, waveform).
//
// Two halves behind one header:
//   AudioAnalyzer  pure code on sample buffers (aubio for onsets and tempo, FFTW for the spectrum);
//                  no JACK, so tests feed it synthetic signals.
//   AudioInput     a JACK client with one input port; its process callback only copies samples
//                  into a lock-free ring, and Poll() (render thread) analyses what arrived.
//
// Usage in `live` (render thread, once per frame):
//   std::string status;
//   std::unique_ptr<AudioInput> audio = AudioInput::Open(desc, &status);   // null: no JACK server
//   if (!status.empty()) log(status);                    // one line; the show goes on without audio
//   ...
//   if (audio) {
//       AudioFeatures f = audio->Poll(now);              // the audio since the last frame
//       queue.Push(AudioFeatureEvent(f, now));           // mapping + recorder, like a knob
//       isfInputs.audio = audio->Textures();             // ISF audio / audioFFT inputs
//   }
// Offline (tests, a WAV): AudioAnalyzer a; a.Process(samples, n); AudioFeatures f = a.TakeFeatures();
//
// Threads: the JACK process thread touches only the ring and two atomics; AudioInput's analysis
// thread drains the ring every 5 ms and publishes features under a mutex held only for a copy
// (aubio's beat tracker takes ~4 ms every ~1.4 s: that must not land on a frame); Poll() takes
// the latest features (see jack_input.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/audio_features.h"

namespace sdfvj {

// Bins of the spectrum and samples of the waveform handed to ISF (audioFFT / audio inputs).
constexpr int kAudioBins = 512;
// Band edges in Hz: bass is [20, 250), mid [250, 4000), high [4000, Nyquist).
constexpr float kBassLowHz = 20.0f, kBassMidHz = 250.0f, kMidHighHz = 4000.0f;

// Zero fields mean the defaults.
struct AudioAnalyzerDesc {
    int sampleRate = 0;        // Hz; 0 = 48000
    float onsetThreshold = 0;  // aubio peak-picking threshold; 0 = aubio's default (0.3)
    float silenceDb = 0;       // below this (dBFS) no onsets or beats; 0 = -60
};

// What the analysis last saw: a 512-bin magnitude spectrum (0..1, dBFS mapped -80..0 -> 0..1;
// bin k is k * SampleRate / 1024 Hz) and the last 512 samples (-1..1).
struct AudioSpectrum {
    std::vector<float> spectrum = std::vector<float>(kAudioBins, 0.0f);
    std::vector<float> waveform = std::vector<float>(kAudioBins, 0.0f);
};

// Owns the aubio and FFTW objects (created and destroyed on one thread: FFTW's planner is not
// thread-safe). Onsets and beats are detected per 512-sample hop; level, bands and spectrum are
// computed over the last 1024 samples when features are taken.
class AudioAnalyzer {
public:
    explicit AudioAnalyzer(const AudioAnalyzerDesc& desc = {});
    ~AudioAnalyzer();
    AudioAnalyzer(const AudioAnalyzer&) = delete;
    AudioAnalyzer& operator=(const AudioAnalyzer&) = delete;

    // Feeds mono samples (-1..1), any count; non-finite samples are read as 0.
    void Process(const float* samples, size_t count);
    // The features now; onset/beat are "since the previous TakeFeatures" and are cleared.
    // Also refreshes Spectrum().
    AudioFeatures TakeFeatures();
    const AudioSpectrum& Spectrum() const { return spectrum_; }

    int SampleRate() const { return rate_; }
    float BinHz() const { return float(rate_) / float(2 * kAudioBins); }
    double Seconds() const { return double(samples_) / rate_; }   // audio analysed so far
    uint64_t Onsets() const { return onsets_; }                   // counted since start
    uint64_t Beats() const { return beats_; }

private:
    struct Aubio;
    std::unique_ptr<Aubio> aubio_;
    int rate_ = 48000;
    float silenceDb_ = -60.0f;
    std::vector<float> history_;   // ring of the last 1024 samples
    size_t historyPos_ = 0;
    std::vector<float> hop_;       // samples waiting for a full hop
    uint64_t samples_ = 0, onsets_ = 0, beats_ = 0;
    uint64_t quietHops_ = 1u << 30;   // hops since one was above silenceDb
    bool onsetPulse_ = false, beatPulse_ = false;
    double lastBeat_ = -1.0;       // seconds (analysed-audio clock)
    float bpm_ = 0.0f;
    AudioSpectrum spectrum_;
};

// dBFS of an amplitude (floor -120).
float AmplitudeDb(float amplitude);
// The largest bin of a spectrum (ties: the lowest).
int PeakBin(const std::vector<float>& spectrum);

// ---------------------------------------------------------------------------------------------
// JACK
// ---------------------------------------------------------------------------------------------

// Zero fields mean the defaults.
struct AudioInputDesc {
    std::string clientName;    // JACK client name; "" = "sdfvj-audio"
    std::string portName;      // input port; "" = "in"
    std::string connect;       // output port to connect from ("system:capture_1"); "" = none
    float onsetThreshold = 0;  // passed to AudioAnalyzerDesc
    size_t ringSamples = 0;    // ring capacity, rounded up to a power of two; 0 = 65536
    std::string recordWav;     // also write the analysed audio to this WAV (wav.h); "" = don't
};

// A JACK client with one mono input port. Owns the client (RAII); the process callback pushes
// samples into a single-producer single-consumer ring and never blocks or allocates.
class AudioInput {
public:
    // Null, with one line in *status ("audio: no JACK server (...) — the show goes on without
    // audio"), when there is no server or the port cannot be made. On success *status says which
    // port listens (and to what it is connected).
    static std::unique_ptr<AudioInput> Open(const AudioInputDesc& desc, std::string* status);
    ~AudioInput();
    AudioInput(const AudioInput&) = delete;
    AudioInput& operator=(const AudioInput&) = delete;

    // Render thread: the latest features the analysis thread published (onset/beat: any since
    // the last call) and a copy of its spectrum and waveform for Textures(). Never waits for the
    // analysis. `now` (the take's clock) only places the recorded WAV's first sample on it.
    AudioFeatures Poll(double now);
    const AudioSpectrum& Textures() const { return textures_; }   // as of the last Poll()

    std::string PortName() const;      // full name, "sdfvj-audio:in"
    int SampleRate() const { return rate_; }
    float BinHz() const { return float(rate_) / float(2 * kAudioBins); }
    uint64_t Overruns() const;         // samples dropped because Poll() fell behind
    bool ServerGone() const;           // the server shut down; Poll() then sees no new audio
    // desc.recordWav: samples written so far, and the writer's first error ("" if none).
    uint64_t RecordedSamples() const;
    std::string RecordError() const;

    struct Impl;

private:
    AudioInput(std::unique_ptr<Impl> impl, int sampleRate);
    std::unique_ptr<Impl> impl_;   // the client, ring, analysis thread and published features
    int rate_ = 48000;
    AudioSpectrum textures_;
};

}  // namespace sdfvj
