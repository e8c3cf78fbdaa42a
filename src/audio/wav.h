// WAV beside a take: the audio `live --record take.mid --audio PORT` analysed, written as
// take.mid.wav while the show runs, and read back by `render --replay take.mid` for ISF
// audio/audioFFT inputs (docs/audio.md, "Replay").
//
//   WavRecorder rec;                                   // live: AudioInput's analysis thread
//   if (!rec.Open("take.mid.wav", 48000, &error)) ...  // a status line, the show goes on
//   rec.Append(samples, n);                            // never blocks on disk
//   rec.NoteClock(showTime, samplesAppendedSoFar);     // where sample 0 lies on the take's clock
//   rec.Close();
//
//   WavAudio wav;
//   if (!ReadWav("take.mid.wav", &wav, &error)) ...    // "take.mid.wav: byte 36: ..., expected ..."
//   AudioReplay replay(std::move(wav));
//   const AudioSpectrum& s = replay.At(frameTime);     // spectrum + waveform as live computed them
//
// File: RIFF/WAVE, `fmt ` IEEE float 32-bit mono (format 3), `fact` (sample count), `sdfv` (our
// chunk: the take time of sample 0 as a little-endian double; other readers skip it), `data`.
// The recorder writes like the take recorder: new samples after the data, fdatasync, then the
// sizes (and origin) that cover them, fdatasync; so a crash or SIGKILL leaves a readable file
// holding all but the last flush interval (0.5 s) of audio.
// Standard library and POSIX file calls only.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "audio/audio.h"
#include "core/durable_file.h"

namespace sdfvj {

// The WAV path `live --record TAKE` writes beside the take: TAKE + ".wav".
std::string TakeWavPath(const std::string& takePath);

struct WavAudio {
    int sampleRate = 48000;
    std::vector<float> samples;   // mono (channel 0 of a multi-channel file), -1..1
    double origin = 0.0;          // take time (seconds) of samples[0]; 0 without an `sdfv` chunk
    bool hasOrigin = false;
};

// Reads a RIFF/WAVE file: PCM 16/24/32-bit or IEEE float 32/64-bit, any channel count (channel
// 0 is used), at most 1 GiB. Every field is checked; on failure *error is one line
// "path: byte N: what is wrong, expected what" and *out is untouched. A data chunk whose size
// runs past the end of the file is an error (the recorder never writes one).
bool ReadWav(const std::string& path, WavAudio* out, std::string* error);
bool ParseWav(const uint8_t* data, size_t size, const std::string& name, WavAudio* out, std::string* error);

// Crash-safe incremental writer of mono float WAVs (see the file comment).
class WavRecorder {
public:
    WavRecorder() = default;
    ~WavRecorder();   // Close()s
    WavRecorder(const WavRecorder&) = delete;
    WavRecorder& operator=(const WavRecorder&) = delete;

    // Creates (truncates) `path` with an empty, valid WAV. False + *error ("path: cannot ...").
    bool Open(const std::string& path, int sampleRate, std::string* error, double flushInterval = 0.5);
    bool IsOpen() const { return fd_ >= 0; }
    // Appends samples to a memory buffer (any one thread; a mutex held for a copy).
    void Append(const float* samples, size_t n);
    // The take's clock read `showTime` when `appended` samples had been appended: sample 0 lies at
    // showTime - appended / rate. The earliest estimate of the first two seconds is kept (the
    // samples reach the analysis a little after they were played, never before).
    void NoteClock(double showTime, uint64_t appended);
    void Flush();   // writes and syncs what was appended, now (blocking)
    void Close();
    uint64_t Appended() const { return appended_.load(); }
    std::string Error() const;   // the first I/O error, "" if none

private:
    void WritePending();

    int fd_ = -1;
    std::string path_;
    int rate_ = 48000;
    double flushInterval_ = 0.5;
    mutable std::mutex mutex_;      // guards pending_, origin_, error_
    std::vector<float> pending_;
    double origin_ = 0.0;
    bool hasOrigin_ = false;
    std::string error_;
    std::mutex io_;                 // one writer of the file at a time
    uint64_t dataBytes_ = 0;        // on disk, covered by the header
    std::atomic<uint64_t> appended_{0};
    PeriodicFlush flusher_;         // WritePending() every flushInterval_
};

// Spectrum and waveform of a WAV at any time of the take, computed by AudioAnalyzer from the
// 1024 samples before that time's sample (the same samples give the same bytes: what `live`
// showed, and the same for every frame range). Before sample 0 and after the end: silence.
// A time's sample: from the anchors (the /sdfvj/audio events' wavSample: at an event's time the
// sample `live` analysed up to, between two events onwards at the sample rate but not past the
// next one's), else origin + time * rate (a WAV from elsewhere: origin 0 without an sdfv chunk).
class AudioReplay {
public:
    explicit AudioReplay(WavAudio wav);
    ~AudioReplay();
    // (take time, WAV sample) pairs, any order.
    void SetAnchors(std::vector<std::pair<double, int64_t>> anchors);
    int64_t SampleAt(double takeTime) const;
    // Times should not go backwards much (each call feeds at most the 1024 samples it needs).
    const AudioSpectrum& At(double takeTime);
    const WavAudio& Wav() const { return wav_; }

private:
    WavAudio wav_;
    std::vector<std::pair<double, int64_t>> anchors_;   // sorted by time, samples non-decreasing
    std::unique_ptr<AudioAnalyzer> analyzer_;
    int64_t fed_ = 0;   // samples [.., fed_) are in the analyzer's history
};

}  // namespace sdfvj
