// AudioAnalyzer: samples -> level, bands, 512-bin spectrum, waveform (FFTW) and onsets, beats,
// tempo (aubio). Pure computation on buffers: the same samples give the same features, so tests
// drive it with synthetic signals and a WAV would replay exactly.
#include <fftw3.h>

extern "C" {
#include <aubio/aubio.h>
}

#include <algorithm>
#include <cmath>

#include "audio/audio.h"

namespace sdfvj {

namespace {
constexpr int kWindow = 2 * kAudioBins;   // 1024-sample FFT -> bins 0..511 used
constexpr int kHop = 512;                 // aubio hop: ~10.7 ms at 48 kHz
constexpr float kBandFloorDb = -60.0f;    // level and bands: -60..0 dBFS -> 0..1
constexpr float kSpectrumFloorDb = -80.0f;
constexpr float kPi = 3.14159265358979f;

float MapDb(float db, float floorDb) { return std::clamp((db - floorDb) / -floorDb, 0.0f, 1.0f); }
}  // namespace

float AmplitudeDb(float amplitude) {
    return amplitude > 1e-6f ? std::max(20.0f * std::log10(amplitude), -120.0f) : -120.0f;
}

int PeakBin(const std::vector<float>& s) {
    return s.empty() ? -1 : int(std::max_element(s.begin(), s.end()) - s.begin());
}

// aubio and FFTW objects; made and freed on the analyzer's thread.
struct AudioAnalyzer::Aubio {
    aubio_onset_t* onset = nullptr;
    aubio_tempo_t* tempo = nullptr;
    fvec_t* in = nullptr;
    fvec_t* out = nullptr;
    float* fftIn = nullptr;
    fftwf_complex* fftOut = nullptr;
    fftwf_plan plan = nullptr;
    std::vector<float> window;
    uint_t lastBeatSample = 0;
    ~Aubio() {
        if (onset) del_aubio_onset(onset);
        if (tempo) del_aubio_tempo(tempo);
        if (in) del_fvec(in);
        if (out) del_fvec(out);
        if (plan) fftwf_destroy_plan(plan);
        if (fftIn) fftwf_free(fftIn);
        if (fftOut) fftwf_free(fftOut);
    }
};

AudioAnalyzer::AudioAnalyzer(const AudioAnalyzerDesc& desc) : aubio_(std::make_unique<Aubio>()) {
    rate_ = desc.sampleRate > 0 ? desc.sampleRate : 48000;
    silenceDb_ = desc.silenceDb < 0 ? desc.silenceDb : -60.0f;
    Aubio& a = *aubio_;
    a.onset = new_aubio_onset("default", kWindow, kHop, uint_t(rate_));
    a.tempo = new_aubio_tempo("default", kWindow, kHop, uint_t(rate_));
    // Programmer bug or a broken libaubio: aubio only fails on invalid sizes or methods.
    if (!a.onset || !a.tempo) std::abort();
    aubio_onset_set_silence(a.onset, silenceDb_);
    aubio_tempo_set_silence(a.tempo, silenceDb_);
    if (desc.onsetThreshold > 0) aubio_onset_set_threshold(a.onset, desc.onsetThreshold);
    a.in = new_fvec(kHop);
    a.out = new_fvec(2);
    a.fftIn = fftwf_alloc_real(kWindow);
    a.fftOut = fftwf_alloc_complex(kWindow / 2 + 1);
    // FFTW_ESTIMATE: no timing runs at start-up, and the same plan (same bytes) every run.
    a.plan = fftwf_plan_dft_r2c_1d(kWindow, a.fftIn, a.fftOut, FFTW_ESTIMATE);
    a.window.resize(kWindow);
    for (int i = 0; i < kWindow; ++i) a.window[size_t(i)] = 0.5f - 0.5f * std::cos(2.0f * kPi * float(i) / kWindow);
    history_.assign(kWindow, 0.0f);
    hop_.reserve(kHop);
}

AudioAnalyzer::~AudioAnalyzer() = default;

void AudioAnalyzer::Process(const float* samples, size_t count) {
    Aubio& a = *aubio_;
    for (size_t i = 0; i < count; ++i) {
        const float s = std::isfinite(samples[i]) ? samples[i] : 0.0f;
        history_[historyPos_] = s;
        historyPos_ = (historyPos_ + 1) % history_.size();
        hop_.push_back(s);
        ++samples_;
        if (hop_.size() < size_t(kHop)) continue;
        std::copy(hop_.begin(), hop_.end(), a.in->data);
        hop_.clear();
        aubio_onset_do(a.onset, a.in, a.out);
        if (a.out->data[0] != 0) {
            onsetPulse_ = true;
            ++onsets_;
        }
        aubio_tempo_do(a.tempo, a.in, a.out);
        // out[0] is the beat's fraction of the hop, which is 0 for a beat on the hop's first
        // sample: a new "last beat" position is the reliable sign of a beat.
        const uint_t last = aubio_tempo_get_last(a.tempo);
        // aubio moves its last beat in silence too (it keeps predicting): a beat after a second
        // without sound is no beat (gaps between drum hits are not silence).
        const bool moved = last != a.lastBeatSample;
        a.lastBeatSample = last;
        quietHops_ = aubio_silence_detection(a.in, silenceDb_) ? quietHops_ + 1 : 0;
        if (moved && quietHops_ * kHop < uint64_t(rate_)) {
            beatPulse_ = true;
            ++beats_;
            lastBeat_ = aubio_tempo_get_last_s(a.tempo);
            const float bpm = aubio_tempo_get_bpm(a.tempo);
            if (std::isfinite(bpm) && bpm > 0) bpm_ = bpm;
        }
    }
}

AudioFeatures AudioAnalyzer::TakeFeatures() {
    Aubio& a = *aubio_;
    // The last 1024 samples, oldest first: waveform, level and the windowed FFT.
    double sumSquares = 0;
    for (int i = 0; i < kWindow; ++i) {
        const float s = history_[(historyPos_ + size_t(i)) % history_.size()];
        sumSquares += double(s) * s;
        a.fftIn[i] = s * a.window[size_t(i)];
        if (i >= kWindow - kAudioBins) spectrum_.waveform[size_t(i - (kWindow - kAudioBins))] = s;
    }
    fftwf_execute(a.plan);

    // Amplitude per bin: a full-scale sine in bin k reads 1 (Hann's coherent gain is 1/2).
    const float norm = 2.0f / (0.5f * kWindow);
    double band[3] = {0, 0, 0};
    const float binHz = BinHz();
    for (int k = 0; k < kAudioBins; ++k) {
        const float re = a.fftOut[k][0], im = a.fftOut[k][1];
        const float amp = std::sqrt(re * re + im * im) * norm;
        spectrum_.spectrum[size_t(k)] = MapDb(AmplitudeDb(amp), kSpectrumFloorDb);
        const float hz = float(k) * binHz;
        const int b = hz < kBassLowHz ? -1 : hz < kBassMidHz ? 0 : hz < kMidHighHz ? 1 : 2;
        if (b >= 0) band[b] += double(amp) * amp;
    }
    // Bins above 511 (up to Nyquist) belong to the high band too.
    for (int k = kAudioBins; k <= kWindow / 2; ++k) {
        const float re = a.fftOut[k][0], im = a.fftOut[k][1];
        const float amp = std::sqrt(re * re + im * im) * norm;
        band[2] += double(amp) * amp;
    }

    AudioFeatures f;
    const float rms = float(std::sqrt(sumSquares / kWindow));
    f.levelDb = AmplitudeDb(rms);
    f.level = MapDb(f.levelDb, kBandFloorDb);
    // A sine spreads over ~1.5 bins of Hann's (equivalent noise bandwidth): divide it out so a
    // band holding one sine of amplitude A reads A.
    float* bands[3] = {&f.bass, &f.mid, &f.high};
    for (int b = 0; b < 3; ++b) *bands[b] = MapDb(AmplitudeDb(float(std::sqrt(band[b] / 1.5))), kBandFloorDb);
    f.onset = onsetPulse_;
    f.beat = beatPulse_;
    onsetPulse_ = beatPulse_ = false;
    f.bpm = bpm_;
    if (bpm_ > 0 && lastBeat_ >= 0) {
        const double beats = (Seconds() - lastBeat_) * bpm_ / 60.0;
        f.beatPhase = float(beats - std::floor(beats));
    }
    return f;
}

}  // namespace sdfvj
