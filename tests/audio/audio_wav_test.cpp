// The WAV beside a take (src/audio/wav.h): the recorder's file reads back bit for bit with its
// origin, damaged files are one "file: byte N: ..., expected ..." line, a SIGKILLed recorder keeps
// all but the last second, and AudioReplay's spectrum depends only on the time asked for.
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "audio/wav.h"
#include "signals.h"

using namespace sdfvj;
namespace fs = std::filesystem;

namespace {

std::string TempPath(const std::string& name) {
    const fs::path dir = fs::path(SDFVJ_AUDIO_OUT) / ("wav-" + std::to_string(getpid()));
    fs::create_directories(dir);
    return (dir / name).string();
}

std::vector<uint8_t> Slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}

void Spit(const std::string& path, const std::vector<uint8_t>& bytes) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

double Now() {
    timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
}

// Sample i of the pattern the crash test records: a ramp no two neighbours share.
float Pattern(uint64_t i) { return float(int(i % 20000) - 10000) / 10000.0f; }

}  // namespace

TEST_CASE("audio wav: the recorder's file reads back bit for bit with the take time of its first sample", "[audio]") {
    const std::string path = TempPath("roundtrip.wav");
    std::vector<float> sine = test::Sine(1000.0f, 0.7f, 0.5, 44100);
    sine[10] = -1.0f;
    sine[11] = 1.0f;
    WavRecorder rec;
    std::string error;
    REQUIRE(rec.Open(path, 44100, &error, 60.0));   // explicit flushes only
    WavAudio wav;
    REQUIRE(ReadWav(path, &wav, &error));   // valid and empty right after Open
    CHECK(wav.samples.empty());
    rec.Append(sine.data(), 10000);
    rec.NoteClock(3.0, 4410);               // 0.1 s of audio seen at 3.0 s: sample 0 at 2.9 s
    rec.NoteClock(3.2, 4410 + 4410);        // later and slower: the earlier estimate stays
    rec.Flush();
    REQUIRE(ReadWav(path, &wav, &error));
    CHECK(wav.samples.size() == 10000);
    rec.Append(sine.data() + 10000, sine.size() - 10000);
    rec.Close();
    INFO(error);
    REQUIRE(ReadWav(path, &wav, &error));
    CHECK(wav.sampleRate == 44100);
    REQUIRE(wav.samples.size() == sine.size());
    CHECK(std::memcmp(wav.samples.data(), sine.data(), sine.size() * sizeof(float)) == 0);
    CHECK(wav.hasOrigin);
    CHECK(wav.origin == Approx(2.9).margin(1e-9));
    CHECK(rec.Error().empty());
}

TEST_CASE("audio wav: 16-bit PCM stereo from another program reads its first channel", "[audio]") {
    std::vector<uint8_t> b = {'R', 'I', 'F', 'F', 0, 0, 0, 0, 'W', 'A', 'V', 'E', 'f', 'm', 't', ' ', 16, 0, 0, 0,
                              1, 0, 2, 0, 0x80, 0xBB, 0, 0, 0, 0xEE, 2, 0, 4, 0, 16, 0,
                              'L', 'I', 'S', 'T', 3, 0, 0, 0, 'a', 'b', 'c', 0,   // odd chunk: padded
                              'd', 'a', 't', 'a', 8, 0, 0, 0, 0x00, 0x40, 0xFF, 0x7F, 0x00, 0xC0, 0, 0};
    WavAudio wav;
    std::string error;
    INFO(error);
    REQUIRE(ParseWav(b.data(), b.size(), "x.wav", &wav, &error));
    CHECK(wav.sampleRate == 48000);
    REQUIRE(wav.samples.size() == 2);
    CHECK(wav.samples[0] == 0.5f);
    CHECK(wav.samples[1] == -0.5f);
    CHECK_FALSE(wav.hasOrigin);
}

TEST_CASE("audio wav: a truncated or garbled WAV is one line with the file, the byte and what was expected", "[audio]") {
    const std::string path = TempPath("damaged.wav");
    {
        WavRecorder rec;
        std::string error;
        REQUIRE(rec.Open(path, 48000, &error));
        std::vector<float> s = test::Sine(440.0f, 0.5f, 0.1);
        rec.Append(s.data(), s.size());
    }
    const std::vector<uint8_t> good = Slurp(path);
    REQUIRE(good.size() == 74 + 4800 * 4);
    struct Case {
        const char* what;
        std::vector<uint8_t> bytes;
        const char* says;
    };
    std::vector<Case> cases;
    cases.push_back({"cut in the data", {good.begin(), good.begin() + 1000}, "chunk 'data' says 19200 bytes"});
    cases.push_back({"cut in the header", {good.begin(), good.begin() + 30}, "chunk 'fmt ' says 18 bytes"});
    cases.push_back({"ten bytes", {good.begin(), good.begin() + 10}, "expected a 12-byte RIFF/WAVE header"});
    std::vector<uint8_t> b = good;
    std::memcpy(b.data(), "RIFX", 4);
    cases.push_back({"not RIFF", b, "byte 0: no 'RIFF' tag"});
    b = good;
    b[20] = 2;   // ADPCM
    cases.push_back({"ADPCM", b, "byte 20: sample format 2, expected 1 (PCM) or 3 (IEEE float)"});
    b = good;
    b[22] = 0;   // no channels
    cases.push_back({"no channels", b, "byte 22: 0 channels, expected 1..64"});
    b = good;
    std::memset(b.data() + 58, 0xFF, 8);   // origin NaN
    cases.push_back({"origin NaN", b, "take time of sample 0 is"});
    b = good;
    b[70] = 0xFF;   // data size 19199: not a whole sample
    b[71] = 0x4A;
    cases.push_back({"odd data size", b, "expected a multiple of the block align 4"});
    // Samples past the data chunk's size (a recorder killed between writing them and the header
    // that covers them): the file reads as the samples its header covers.
    {
        std::vector<uint8_t> longer = good;
        for (int i = 0; i < 6 * 4; ++i) longer.push_back(uint8_t(0x3F + i));
        Spit(path, longer);
        WavAudio wav, whole;
        std::string error;
        REQUIRE(ParseWav(good.data(), good.size(), path, &whole, &error));
        REQUIRE(ReadWav(path, &wav, &error));
        CHECK(wav.samples == whole.samples);
        CHECK(wav.samples.size() == 4800);
    }
    for (const Case& c : cases) {
        INFO(c.what);
        Spit(path, c.bytes);
        WavAudio wav;
        wav.sampleRate = 1234;
        std::string error;
        CHECK_FALSE(ReadWav(path, &wav, &error));
        CHECK(error.rfind(path + ": byte ", 0) == 0);
        CHECK(error.find(c.says) != std::string::npos);
        CHECK(error.find("expected") != std::string::npos);
        CHECK(error.find('\n') == std::string::npos);
        CHECK(wav.sampleRate == 1234);   // untouched
        UNSCOPED_INFO(error);
    }
    WavAudio wav;
    std::string error;
    CHECK_FALSE(ReadWav(path + ".missing", &wav, &error));
    CHECK(error.find(".missing: cannot open") != std::string::npos);
}

TEST_CASE("audio wav: a SIGKILLed recorder keeps all but the last second of the audio", "[audio][slow]") {
    for (double killAt : {1.3, 2.05}) {   // two points in the flush cycle
        const std::string path = TempPath("kill.wav");
        const double origin = Now();
        const pid_t pid = fork();
        REQUIRE(pid >= 0);
        if (pid == 0) {   // the analysis thread of a show: 48 kHz in 5 ms blocks, never closed
            WavRecorder* rec = new WavRecorder();
            std::string error;
            if (!rec->Open(path, 48000, &error)) _exit(3);
            std::vector<float> block;
            for (uint64_t n = 0;;) {
                const uint64_t due = uint64_t((Now() - origin) * 48000);
                block.clear();
                for (; n < due; ++n) block.push_back(Pattern(n));
                rec->Append(block.data(), block.size());
                usleep(5000);
            }
        }
        while (Now() - origin < killAt) usleep(1000);
        kill(pid, SIGKILL);
        const double stoppedAt = Now() - origin;
        int status = 0;
        REQUIRE(waitpid(pid, &status, 0) == pid);
        REQUIRE(WIFSIGNALED(status));
        WavAudio wav;
        std::string error;
        const bool read = ReadWav(path, &wav, &error);
        INFO(error);
        REQUIRE(read);
        INFO("kept " << wav.samples.size() / 48000.0 << " s of audio, recording stopped at " << stoppedAt << " s");
        CHECK(double(wav.samples.size()) >= (stoppedAt - 1.0) * 48000);
        for (size_t i = 0; i < wav.samples.size(); ++i)
            if (wav.samples[i] != Pattern(i)) FAIL("sample " << i << " is " << wav.samples[i] << ", expected " << Pattern(i));
    }
}

TEST_CASE("audio wav: the replayed spectrum is that of the 1024 samples before the time, whatever came before", "[audio]") {
    WavAudio wav;
    wav.sampleRate = 48000;
    wav.origin = 0.25;
    wav.hasOrigin = true;
    wav.samples = test::Sine(1500.0f, 0.5f, 2.0);   // bin 32
    for (size_t i = 48000; i < wav.samples.size(); ++i) wav.samples[i] = 0.5f * float(std::sin(2 * M_PI * 3000.0 * double(i) / 48000));
    AudioReplay frames(wav), jump(wav), back(wav);
    std::vector<float> silent(kAudioBins, 0.0f);
    CHECK(frames.At(0.1).spectrum == silent);   // before the first sample: silence
    for (int f = 4; f <= 40; ++f) frames.At(f / 30.0);
    const AudioSpectrum a = frames.At(41 / 30.0);   // 1.117 s into the WAV: the 3000 Hz half
    CHECK(PeakBin(a.spectrum) == 64);
    CHECK(a.spectrum[64] > 0.9f);   // -6 dBFS reads (80 - 6) / 80
    CHECK(a.spectrum[32] < 0.3f);
    CHECK(jump.At(41 / 30.0).spectrum == a.spectrum);   // a frame range starting here: same bytes
    CHECK(jump.At(41 / 30.0).waveform == a.waveform);
    back.At(1.9);
    CHECK(back.At(41 / 30.0).spectrum == a.spectrum);   // backwards: refilled
    CHECK(PeakBin(frames.At(0.75).spectrum) == 32);
    CHECK(frames.At(3.0).spectrum == silent);   // after the end: silence
}

TEST_CASE("audio wav: the take's feature events place each frame in the WAV, whatever the clocks did", "[audio]") {
    AudioFeatures f;
    f.level = 0.5f;
    f.wavSample = 123456789;
    AudioFeatures g;
    REQUIRE(ReadAudioFeatureEvent(AudioFeatureEvent(f, 2.0), &g));
    CHECK(g.wavSample == 123456789);
    CHECK(g.level == 0.5f);
    f.wavSample = -1;   // not recording: nine floats as before
    CHECK(AudioFeatureEvent(f, 2.0).args.size() == 9);
    REQUIRE(ReadAudioFeatureEvent(AudioFeatureEvent(f, 2.0), &g));
    CHECK(g.wavSample == -1);

    WavAudio wav;
    wav.origin = 0.25;   // used only without anchors
    AudioReplay r(wav);
    CHECK(r.SampleAt(1.25) == 48000);
    // The audio clock ran slow: 2400 samples in 0.1 s of the show between two events.
    r.SetAnchors({{1.1, 50400}, {1.0, 48000}, {1.2, 50000}});   // a smaller later sample reads as the one before
    CHECK(r.SampleAt(1.0) == 48000);          // at an event: the sample live analysed up to
    CHECK(r.SampleAt(1.025) == 49200);        // between: on at the sample rate ...
    CHECK(r.SampleAt(1.09) == 50400);         // ... never past the next event's
    CHECK(r.SampleAt(1.2) == 50400);
    CHECK(r.SampleAt(0.5) == 24000);          // before the first event: back at the sample rate
    CHECK(r.SampleAt(2.2) == 50400 + 48000);  // after the last: on at the sample rate
}
