// A JACK client with one output port that plays a sine (tests/audio: the sound a show listens to).
#pragma once
#include <jack/jack.h>

#include <atomic>
#include <cmath>
#include <string>

#include <catch2/catch.hpp>

namespace sdfvj::test {

// A JACK client with one output port that plays a sine whose frequency can change while it runs.
struct SinePlayer {
    jack_client_t* client = nullptr;
    jack_port_t* port = nullptr;
    std::atomic<float> hz{1000.0f};
    std::atomic<float> amplitude{0.5f};
    double phase = 0.0;   // process thread only
    double rate = 48000.0;

    explicit SinePlayer(const char* name) {
        client = jack_client_open(name, JackNoStartServer, nullptr);
        REQUIRE(client != nullptr);
        rate = jack_get_sample_rate(client);
        port = jack_port_register(client, "out", JACK_DEFAULT_AUDIO_TYPE, JackPortIsOutput, 0);
        REQUIRE(port != nullptr);
        jack_set_process_callback(client, &SinePlayer::Process, this);
        REQUIRE(jack_activate(client) == 0);
    }
    ~SinePlayer() {
        jack_deactivate(client);
        jack_client_close(client);
    }
    static int Process(jack_nframes_t n, void* arg) {
        SinePlayer& p = *static_cast<SinePlayer*>(arg);
        float* out = static_cast<float*>(jack_port_get_buffer(p.port, n));
        const double step = 2.0 * M_PI * p.hz.load() / p.rate;
        const float a = p.amplitude.load();
        for (jack_nframes_t i = 0; i < n; ++i) {
            out[i] = a * float(std::sin(p.phase));
            p.phase = std::fmod(p.phase + step, 2.0 * M_PI);
        }
        return 0;
    }
    std::string PortName() const { return jack_port_name(port); }
};

}  // namespace sdfvj::test
