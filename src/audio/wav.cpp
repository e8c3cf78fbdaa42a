// WAV beside a take: the crash-safe recorder, the checked reader and the replay of its spectrum.
// Layout and the write order are in wav.h.
#include "audio/wav.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>

namespace sdfvj {

namespace {

// Offsets of the header the recorder writes (74 bytes, then the samples).
constexpr uint64_t kRiffSizeAt = 4, kFactCountAt = 46, kOriginAt = 58, kDataSizeAt = 70, kDataAt = 74;
constexpr uint64_t kMaxWavBytes = uint64_t(1) << 30;

void PutU16(std::vector<uint8_t>* o, uint32_t v) { o->insert(o->end(), {uint8_t(v), uint8_t(v >> 8)}); }
void PutU32(std::vector<uint8_t>* o, uint32_t v) {
    o->insert(o->end(), {uint8_t(v), uint8_t(v >> 8), uint8_t(v >> 16), uint8_t(v >> 24)});
}
void PutTag(std::vector<uint8_t>* o, const char* tag) { o->insert(o->end(), tag, tag + 4); }
void PutF64(std::vector<uint8_t>* o, double d) {
    uint64_t v;
    std::memcpy(&v, &d, 8);
    for (int i = 0; i < 8; ++i) o->push_back(uint8_t(v >> (8 * i)));
}
uint32_t U16(const uint8_t* p) { return uint32_t(p[0]) | uint32_t(p[1]) << 8; }
uint32_t U32(const uint8_t* p) { return U16(p) | U16(p + 2) << 16; }

}  // namespace

std::string TakeWavPath(const std::string& takePath) { return takePath + ".wav"; }

// ---------------------------------------------------------------------------------------------
// Reader
// ---------------------------------------------------------------------------------------------

bool ParseWav(const uint8_t* d, size_t size, const std::string& name, WavAudio* out, std::string* error) {
    auto fail = [&](uint64_t at, const std::string& what) {
        *error = name + ": byte " + std::to_string(at) + ": " + what;
        return false;
    };
    if (size < 12) return fail(size, "the file ends after " + std::to_string(size) + " bytes, expected a 12-byte RIFF/WAVE header");
    if (std::memcmp(d, "RIFF", 4) != 0) return fail(0, "no 'RIFF' tag, expected a WAV file (RIFF/WAVE)");
    if (std::memcmp(d + 8, "WAVE", 4) != 0) return fail(8, "RIFF form is not 'WAVE', expected a WAV file");
    bool haveFmt = false, haveData = false;
    uint32_t format = 0, channels = 0, rate = 0, blockAlign = 0, bits = 0;
    WavAudio wav;
    uint64_t pos = 12;
    while (pos + 8 <= size) {
        const uint8_t* c = d + pos;
        const std::string tag(reinterpret_cast<const char*>(c), 4);
        const uint64_t len = U32(c + 4);
        const uint8_t* body = c + 8;
        // After the samples, bytes no header covers yet: a recorder stopped (killed) between writing
        // samples and the sizes that cover them (WavRecorder::WritePending). Its audio ends there.
        if (pos + 8 + len > size && haveData) break;
        if (pos + 8 + len > size)
            return fail(pos + 4, "chunk '" + tag + "' says " + std::to_string(len) + " bytes but the file has " +
                                     std::to_string(size - pos - 8) + " left, expected a complete WAV (the file is cut)");
        if (tag == "fmt ") {
            if (len < 16) return fail(pos + 4, "fmt chunk of " + std::to_string(len) + " bytes, expected at least 16");
            format = U16(body);
            channels = U16(body + 2);
            rate = U32(body + 4);
            blockAlign = U16(body + 12);
            bits = U16(body + 14);
            if (format == 0xFFFE) {   // WAVE_FORMAT_EXTENSIBLE: the sub-format's first two bytes
                if (len < 40) return fail(pos + 8, "extensible fmt chunk of " + std::to_string(len) + " bytes, expected 40");
                format = U16(body + 24);
            }
            if (format != 1 && format != 3) return fail(pos + 8, "sample format " + std::to_string(format) + ", expected 1 (PCM) or 3 (IEEE float)");
            if (channels < 1 || channels > 64) return fail(pos + 10, std::to_string(channels) + " channels, expected 1..64");
            if (rate < 1000 || rate > 384000) return fail(pos + 12, "sample rate " + std::to_string(rate) + " Hz, expected 1000..384000");
            const bool bitsOk = format == 1 ? (bits == 16 || bits == 24 || bits == 32) : (bits == 32 || bits == 64);
            if (!bitsOk) return fail(pos + 22, std::to_string(bits) + " bits per sample, expected " + (format == 1 ? "16, 24 or 32 (PCM)" : "32 or 64 (float)"));
            if (blockAlign != channels * bits / 8)
                return fail(pos + 20, "block align " + std::to_string(blockAlign) + ", expected channels x bytes per sample = " +
                                          std::to_string(channels * bits / 8));
            haveFmt = true;
        } else if (tag == "sdfv") {
            if (len < 8) return fail(pos + 4, "sdfv chunk of " + std::to_string(len) + " bytes, expected 8 (the take time of sample 0)");
            uint64_t v = 0;
            for (int i = 0; i < 8; ++i) v |= uint64_t(body[i]) << (8 * i);
            double origin;
            std::memcpy(&origin, &v, 8);
            if (!std::isfinite(origin) || std::fabs(origin) > 1e7)
                return fail(pos + 8, "take time of sample 0 is " + std::to_string(origin) + ", expected seconds within +-1e7");
            wav.origin = origin;
            wav.hasOrigin = true;
        } else if (tag == "data") {
            if (!haveFmt) return fail(pos, "data chunk before the fmt chunk, expected fmt first");
            if (haveData) return fail(pos, "a second data chunk, expected one");
            if (len % blockAlign != 0)
                return fail(pos + 4, "data chunk of " + std::to_string(len) + " bytes, expected a multiple of the block align " +
                                         std::to_string(blockAlign));
            const size_t frames = size_t(len / blockAlign);
            wav.samples.resize(frames);
            for (size_t i = 0; i < frames; ++i) {
                const uint8_t* s = body + i * blockAlign;   // channel 0
                float v = 0.0f;
                if (format == 3 && bits == 32) {
                    uint32_t u = U32(s);
                    std::memcpy(&v, &u, 4);
                } else if (format == 3) {
                    uint64_t u = uint64_t(U32(s)) | uint64_t(U32(s + 4)) << 32;
                    double x;
                    std::memcpy(&x, &u, 8);
                    v = float(x);
                } else if (bits == 16) {
                    v = float(int16_t(U16(s))) / 32768.0f;
                } else if (bits == 24) {
                    const uint32_t u = uint32_t(s[0]) << 8 | uint32_t(s[1]) << 16 | uint32_t(s[2]) << 24;
                    v = float(int32_t(u) >> 8) / 8388608.0f;   // 3 bytes, sign-extended
                } else {
                    v = float(double(int32_t(U32(s))) / 2147483648.0);
                }
                wav.samples[i] = std::isfinite(v) ? std::clamp(v, -1.0f, 1.0f) : 0.0f;
            }
            haveData = true;
        }
        pos += 8 + len + (len & 1);   // chunks are padded to even sizes
    }
    if (!haveFmt) return fail(12, "no fmt chunk, expected one before the samples");
    if (!haveData) return fail(size, "no data chunk, expected the samples");
    wav.sampleRate = int(rate);
    *out = std::move(wav);
    return true;
}

bool ReadWav(const std::string& path, WavAudio* out, std::string* error) {
    std::ifstream f(path, std::ios::binary | std::ios::ate);
    if (!f) {
        *error = path + ": cannot open: " + std::strerror(errno);
        return false;
    }
    const std::streamoff n = f.tellg();
    if (n < 0 || uint64_t(n) > kMaxWavBytes) {
        *error = path + ": " + std::to_string(n) + " bytes, expected a WAV of at most 1 GiB";
        return false;
    }
    std::vector<uint8_t> bytes(static_cast<size_t>(n));
    f.seekg(0);
    if (n > 0 && !f.read(reinterpret_cast<char*>(bytes.data()), n)) {
        *error = path + ": read failed, expected " + std::to_string(n) + " bytes";
        return false;
    }
    return ParseWav(bytes.data(), bytes.size(), path, out, error);
}

// ---------------------------------------------------------------------------------------------
// Recorder
// ---------------------------------------------------------------------------------------------

WavRecorder::~WavRecorder() { Close(); }

bool WavRecorder::Open(const std::string& path, int sampleRate, std::string* error, double flushInterval) {
    Close();
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        *error = path + ": cannot open for recording: " + std::strerror(errno);
        return false;
    }
    rate_ = sampleRate > 0 ? sampleRate : 48000;
    std::vector<uint8_t> h;
    PutTag(&h, "RIFF");
    PutU32(&h, uint32_t(kDataAt - 8));
    PutTag(&h, "WAVE");
    PutTag(&h, "fmt ");
    PutU32(&h, 18);
    PutU16(&h, 3);   // IEEE float: the samples the analysis saw, bit for bit
    PutU16(&h, 1);
    PutU32(&h, uint32_t(rate_));
    PutU32(&h, uint32_t(rate_) * 4);
    PutU16(&h, 4);
    PutU16(&h, 32);
    PutU16(&h, 0);
    PutTag(&h, "fact");
    PutU32(&h, 4);
    PutU32(&h, 0);
    PutTag(&h, "sdfv");
    PutU32(&h, 8);
    PutF64(&h, 0.0);
    PutTag(&h, "data");
    PutU32(&h, 0);
    if (h.size() != kDataAt || !PwriteAll(fd, h.data(), h.size(), 0)) {
        *error = path + ": write failed: " + std::strerror(errno);
        ::close(fd);
        return false;
    }
    ::fdatasync(fd);
    fd_ = fd;
    path_ = path;
    flushInterval_ = flushInterval > 0 ? flushInterval : 0.5;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        pending_.clear();
        origin_ = 0.0;
        hasOrigin_ = false;
        error_.clear();
    }
    dataBytes_ = 0;
    appended_ = 0;
    flusher_.Start(flushInterval_, [this] { WritePending(); });
    return true;
}

void WavRecorder::Append(const float* samples, size_t n) {
    if (fd_ < 0 || n == 0) return;
    std::lock_guard<std::mutex> lock(mutex_);
    pending_.insert(pending_.end(), samples, samples + n);
    appended_.fetch_add(n);
}

void WavRecorder::NoteClock(double showTime, uint64_t appended) {
    if (fd_ < 0 || appended == 0 || !std::isfinite(showTime)) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (hasOrigin_ && appended > uint64_t(2 * rate_)) return;   // settled: the clocks may drift apart later
    const double origin = showTime - double(appended) / rate_;
    if (!hasOrigin_ || origin < origin_) origin_ = origin;
    hasOrigin_ = true;
}

void WavRecorder::Flush() {
    if (fd_ >= 0) WritePending();
}

void WavRecorder::Close() {
    if (fd_ < 0) return;
    flusher_.Stop();
    WritePending();
    ::close(fd_);
    fd_ = -1;
}

std::string WavRecorder::Error() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return error_;
}

void WavRecorder::WritePending() {
    std::lock_guard<std::mutex> io(io_);
    std::vector<float> samples;
    double origin;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        samples.swap(pending_);
        origin = origin_;
    }
    // The file may not grow past what a RIFF size can say (4 GiB; ReadWav takes 1 GiB: ~1.5 h).
    const uint64_t room = (kMaxWavBytes - kDataAt - dataBytes_) / 4;
    if (samples.size() > room) {
        samples.resize(size_t(room));
        std::lock_guard<std::mutex> lock(mutex_);
        if (error_.empty()) error_ = path_ + ": 1 GiB written, the rest of the audio is not recorded";
    }
    std::vector<uint8_t> bytes;
    bytes.reserve(samples.size() * 4);
    for (float s : samples) {
        uint32_t u;
        std::memcpy(&u, &s, 4);
        PutU32(&bytes, u);
    }
    // 1. the samples after the data on disk; 2. sync; 3. the sizes and origin that cover them; sync.
    if (!bytes.empty() && !PwriteAll(fd_, bytes.data(), bytes.size(), kDataAt + dataBytes_)) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (error_.empty()) error_ = path_ + ": write failed: " + std::strerror(errno) + "; this audio is lost, later writes are tried";
        return;
    }
    if (!bytes.empty()) ::fdatasync(fd_);
    dataBytes_ += bytes.size();
    auto patch = [&](uint64_t at, const std::vector<uint8_t>& v) { return PwriteAll(fd_, v.data(), v.size(), at); };
    std::vector<uint8_t> riff, fact, org, data;
    PutU32(&riff, uint32_t(kDataAt - 8 + dataBytes_));
    PutU32(&fact, uint32_t(dataBytes_ / 4));
    PutF64(&org, origin);
    PutU32(&data, uint32_t(dataBytes_));
    if (!patch(kDataSizeAt, data) || !patch(kFactCountAt, fact) || !patch(kOriginAt, org) || !patch(kRiffSizeAt, riff)) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (error_.empty()) error_ = path_ + ": header write failed: " + std::strerror(errno);
        return;
    }
    ::fdatasync(fd_);
}

// ---------------------------------------------------------------------------------------------
// Replay
// ---------------------------------------------------------------------------------------------

AudioReplay::AudioReplay(WavAudio wav)
    : wav_(std::move(wav)), analyzer_(std::make_unique<AudioAnalyzer>(AudioAnalyzerDesc{wav_.sampleRate, 0, 0})) {}

AudioReplay::~AudioReplay() = default;

void AudioReplay::SetAnchors(std::vector<std::pair<double, int64_t>> anchors) {
    anchors.erase(std::remove_if(anchors.begin(), anchors.end(), [](const auto& a) { return !std::isfinite(a.first) || a.second < 0; }),
                  anchors.end());
    std::stable_sort(anchors.begin(), anchors.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (size_t i = 1; i < anchors.size(); ++i) anchors[i].second = std::max(anchors[i].second, anchors[i - 1].second);
    anchors_ = std::move(anchors);
}

int64_t AudioReplay::SampleAt(double t) const {
    const double rate = wav_.sampleRate;
    auto samples = [](double x) { return std::isfinite(x) ? int64_t(std::llround(std::clamp(x, -1e15, 1e15))) : int64_t(0); };
    if (anchors_.empty()) return samples((t - wav_.origin) * rate);
    // The last event at or before t (an event reaches the first frame at or after its time).
    auto next = std::upper_bound(anchors_.begin(), anchors_.end(), t + 1e-9, [](double x, const auto& a) { return x < a.first; });
    if (next == anchors_.begin()) return next->second - samples((next->first - t) * rate);
    const auto& prev = *(next - 1);
    const int64_t p = prev.second + samples((t - prev.first) * rate);
    return next == anchors_.end() ? p : std::min(p, next->second);
}

const AudioSpectrum& AudioReplay::At(double takeTime) {
    const int64_t window = 2 * kAudioBins;
    const int64_t p = SampleAt(takeTime);
    // The analyzer's history is the last 1024 samples fed: feeding [p - 1024, p) (or the part of
    // it after what was fed already) leaves it holding exactly samples [p - 1024, p).
    const int64_t from = p < fed_ ? p - window : std::max(fed_, p - window);
    if (p > from) {
        std::vector<float> chunk(size_t(p - from), 0.0f);
        const int64_t n = int64_t(wav_.samples.size());
        for (int64_t i = std::max<int64_t>(from, 0); i < std::min(p, n); ++i) chunk[size_t(i - from)] = wav_.samples[size_t(i)];
        analyzer_->Process(chunk.data(), chunk.size());
        fed_ = p;
    }
    analyzer_->TakeFeatures();
    return analyzer_->Spectrum();
}

}  // namespace sdfvj
