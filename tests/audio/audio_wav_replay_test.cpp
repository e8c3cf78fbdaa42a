// The audio beside a take, end to end: a sine played through JACK's dummy server (the `jackd`
// fixture) into AudioInput recording TAKE.wav while the take records its feature events (what
// `live --record take.mid --audio PORT` does each frame), then `sdfvj render --replay take.mid`
// with an ISF generator whose audioFFT input is drawn one column per bin (tests/audio/files/
// audio_view.fs): the same bytes twice, the sine's bin lit; a damaged WAV is one line and a
// render without audio.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "../replay/proc_util.h"
#include "audio/audio.h"
#include "audio/wav.h"
#include "isf/isf.h"
#include "jack_sine.h"
#include "take/take.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

constexpr int kFps = 30;

// The red channel (the spectrum) of row 0 of a rendered frame, one value per column.
std::vector<int> RedRow(const std::string& png) {
    int w = 0, h = 0;
    std::vector<uint8_t> rgba;
    std::string error;
    INFO(png << ": " << error);
    REQUIRE(LoadImageRgba(png, &w, &h, &rgba, &error));
    std::vector<int> red(static_cast<size_t>(w));
    for (int x = 0; x < w; ++x) red[size_t(x)] = rgba[size_t(x) * 4];
    return red;
}

std::string Frame(const std::string& dir, int i) {
    char name[32];
    std::snprintf(name, sizeof name, "/frame_%05d.png", i);
    return dir + name;
}

std::vector<std::string> RenderArgs(const std::string& take, const std::string& out) {
    return {SDFVJ_BIN, "render", "--scene", SDFVJ_AUDIO_TEST_FILES "/audio_view.fs", "--replay", take, "--size", "512x2",
            "--fps", std::to_string(kFps), "--quiet", "--out", out};
}

}  // namespace

TEST_CASE("audio wav replay: a sine recorded through JACK replays into an ISF audioFFT input, the same bytes twice", "[audio][jack]") {
    const std::string root = SDFVJ_AUDIO_OUT;
    const std::string dir = FreshDir(root, "wav-replay");
    const std::string take = dir + "/take.mid";

    // The show: 1.8 s at ~30 fps, the sine in bin 32 (1500 Hz at 48 kHz) from 0.4 s on.
    SinePlayer player("sdfvj-test-wav-sine");
    player.amplitude = 0.0f;
    AudioInputDesc desc;
    desc.clientName = "sdfvj-test-wav";
    desc.connect = player.PortName();
    desc.recordWav = TakeWavPath(take);
    std::string status, error;
    std::unique_ptr<AudioInput> in = AudioInput::Open(desc, &status);
    INFO(status);
    REQUIRE(in);
    CHECK(status.find("recording it to " + desc.recordWav) != std::string::npos);
    const int bin = 32;
    player.hz = bin * in->BinHz();
    TakeRecorder rec;
    REQUIRE(rec.Open(take, &error));
    const auto start = std::chrono::steady_clock::now();
    auto now = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    int loudFrames = 0;
    while (now() < 1.8) {
        if (now() >= 0.4) player.amplitude = 0.5f;
        const double t = now();
        const AudioFeatures f = in->Poll(t);
        rec.Record(AudioFeatureEvent(f, t));
        loudFrames += PeakBin(in->Textures().spectrum) == bin;
        std::this_thread::sleep_for(std::chrono::milliseconds(1000 / kFps));
    }
    rec.Close(now());
    const uint64_t recorded = in->RecordedSamples();
    CHECK(in->RecordError().empty());
    in.reset();   // closes the WAV
    CHECK(loudFrames > 10);   // the show saw the sine
    WavAudio wav;
    REQUIRE(ReadWav(desc.recordWav, &wav, &error));
    CHECK(wav.samples.size() >= recorded);   // and what the analysis had not reached at the end
    CHECK(wav.hasOrigin);
    CHECK(wav.origin >= -0.1);
    CHECK(wav.origin < 0.5);
    INFO("WAV: " << wav.samples.size() << " samples at " << wav.sampleRate << " Hz from take time " << wav.origin);
    CHECK(double(wav.samples.size()) > 1.0 * wav.sampleRate);
    // Each frame's feature event says where in the WAV its spectrum ended (the replay's anchors).
    Take recordedTake;
    REQUIRE(ReadTake(take, &recordedTake).ok);
    int64_t last = 0;
    for (const ControlEvent& e : recordedTake.events) {
        AudioFeatures f;
        REQUIRE(ReadAudioFeatureEvent(e, &f));
        CHECK(f.wavSample >= last);
        last = f.wavSample;
    }
    CHECK(recordedTake.events.size() > 30);
    CHECK(last > 0);
    CHECK(uint64_t(last) <= wav.samples.size());

    // Twice with the WAV: the same bytes; once with the WAV moved away: silence.
    const std::string a = FreshDir(root, "wav-replay-a"), b = FreshDir(root, "wav-replay-b");
    const pid_t pa = Spawn(RenderArgs(take, a), a + ".log"), pb = Spawn(RenderArgs(take, b), b + ".log");
    const int ra = WaitExit(pa, 90), rb = WaitExit(pb, 90);
    INFO(ReadText(a + ".log") << ReadText(b + ".log"));
    REQUIRE(ra == 0);
    REQUIRE(rb == 0);
    int frames = 0, lit = 0, window = 0;
    for (int i = 0; fs::exists(Frame(a, i)); ++i, ++frames) {
        INFO("frame " << i);
        REQUIRE(ReadText(Frame(a, i)) == ReadText(Frame(b, i)));   // byte for byte
        const std::vector<int> red = RedRow(Frame(a, i));
        REQUIRE(red.size() == 512);
        INFO("red at the sine's bin " << red[bin] << ", at bin 200 " << red[200] << ", at bin 5 " << red[5]);
        // From 0.7 s on the last 1024 samples are all sine: its bin is the peak, near -6 dBFS
        // ((80 - 6) / 80 of 255), and bins far from it are dark. A loaded machine may drop a JACK
        // cycle (a click the show heard too, spread over every bin): most frames, not all.
        if (double(i) / kFps >= 0.7 && double(i) / kFps <= 1.5) {
            ++window;
            lit += red[bin] >= 200 && *std::max_element(red.begin(), red.end()) == red[bin] && red[200] <= 40;
        }
        if (double(i) / kFps <= 0.15) CHECK(red[bin] <= 40);   // before the sine
    }
    CHECK(frames >= 51);
    INFO(lit << " of " << window << " frames between 0.7 and 1.5 s show the sine alone");
    CHECK(lit >= window * 3 / 4);

    const std::string c = FreshDir(root, "wav-replay-none");
    fs::rename(desc.recordWav, dir + "/moved.wav");
    REQUIRE(Run(RenderArgs(take, c), c + ".log", 90) == 0);
    CHECK(RedRow(Frame(c, 30))[bin] == 0);   // no WAV: the input reads silence, as before

    // A garbled WAV (a header cut short, then junk): one line naming it, a render without audio.
    {
        std::vector<uint8_t> bytes;
        std::FILE* f = std::fopen((dir + "/moved.wav").c_str(), "rb");
        REQUIRE(f);
        bytes.resize(50);   // RIFF, fmt and fact: the header up to our sdfv chunk
        REQUIRE(std::fread(bytes.data(), 1, bytes.size(), f) == bytes.size());
        std::fclose(f);
        bytes.insert(bytes.end(), {'d', 'a', 't', 'a', 0xFF, 0xFF, 0, 0, 1, 2, 3});
        f = std::fopen(desc.recordWav.c_str(), "wb");
        std::fwrite(bytes.data(), 1, bytes.size(), f);
        std::fclose(f);
    }
    const std::string d = FreshDir(root, "wav-replay-garbled");
    REQUIRE(Run(RenderArgs(take, d), d + ".log", 90) == 0);
    const std::string log = ReadText(d + ".log");
    INFO(log);
    CHECK(log.find(desc.recordWav + ": byte ") != std::string::npos);
    CHECK(log.find("expected a complete WAV") != std::string::npos);
    CHECK(log.find("rendering without the take's audio") != std::string::npos);
    CHECK(ReadText(Frame(d, 30)) == ReadText(Frame(c, 30)));   // the same frame as without a WAV
}
