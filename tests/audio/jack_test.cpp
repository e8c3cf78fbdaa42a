// AudioInput through a real JACK server (the dummy backend the `jackd` fixture starts): a test
// client plays a sine into sdfvj's input port and the right bin and band move.
#include <jack/jack.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include <catch2/catch.hpp>

#include "audio/audio.h"
#include "jack_sine.h"

using namespace sdfvj;
using sdfvj::test::SinePlayer;

namespace {

// Polls (as a 100 fps render loop would; the analysis thread publishes every 5 ms) until `done` says yes or 3 s pass. The window holds the
// last 1024 samples, so the click of a change in the signal leaves it within a few polls.
template <typename F>
AudioFeatures PollUntil(AudioInput& in, F done) {
    AudioFeatures f;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(3);
    while (std::chrono::steady_clock::now() < end) {
        f = in.Poll(0.0);
        if (done(f)) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return f;
}

}  // namespace

TEST_CASE("audio jack: a sine played into the port moves the right bin and band", "[audio][jack]") {
    SinePlayer player("sdfvj-test-sine");
    AudioInputDesc desc;
    desc.clientName = "sdfvj-test-audio";
    desc.connect = player.PortName();
    std::string status;
    std::unique_ptr<AudioInput> in = AudioInput::Open(desc, &status);
    INFO(status);
    REQUIRE(in);
    CHECK(status.find("listening on JACK port sdfvj-test-audio:in") != std::string::npos);
    CHECK(status.find("connected from sdfvj-test-sine:out") != std::string::npos);
    const float binHz = in->BinHz();

    // 21 bins up (~1 kHz at 48 kHz): a mid-band sine.
    player.hz = 21 * binHz;
    AudioFeatures f = PollUntil(*in, [&](const AudioFeatures& g) { 
        return PeakBin(in->Textures().spectrum) == 21 && g.mid > 0.8f && g.bass < 0.3f && g.high < 0.3f;
    });
    CHECK(PeakBin(in->Textures().spectrum) == 21);
    CHECK(f.mid > 0.8f);
    CHECK(f.bass < 0.3f);
    CHECK(f.high < 0.3f);

    // Down to bin 3 (~140 Hz): the peak and the energy move to the bass band.
    player.hz = 3 * binHz;
    f = PollUntil(*in, [&](const AudioFeatures& g) { 
        return PeakBin(in->Textures().spectrum) == 3 && g.bass > 0.8f && g.mid < 0.3f;
    });
    CHECK(PeakBin(in->Textures().spectrum) == 3);
    CHECK(f.bass > 0.8f);
    CHECK(f.mid < 0.3f);

    // Silence on the wire: the level falls to nothing.
    player.amplitude = 0.0f;
    f = PollUntil(*in, [](const AudioFeatures& g) { return g.level == 0.0f; });
    CHECK(f.level == 0.0f);
    CHECK(in->Overruns() == 0);
    CHECK_FALSE(in->ServerGone());
}

TEST_CASE("audio jack: a port that is not there is a status line, not a failure", "[audio][jack]") {
    AudioInputDesc desc;
    desc.clientName = "sdfvj-test-audio2";
    desc.connect = "no-such-client:out";
    std::string status;
    std::unique_ptr<AudioInput> in = AudioInput::Open(desc, &status);
    REQUIRE(in);
    CHECK(status.find("cannot connect from 'no-such-client:out'") != std::string::npos);
    CHECK(status.find('\n') == std::string::npos);
    in->Poll(0.0);   // runs, unconnected: silence
}
