// No JACK server: AudioInput::Open is null with one clear line, and nothing else happens.
#include <cstdlib>

#include <catch2/catch.hpp>

#include "audio/audio.h"

using namespace sdfvj;

TEST_CASE("audio input: no JACK server gives one line and a null input", "[audio]") {
    // A server name nobody runs: libjack looks for it and gives up (JackNoStartServer).
    const char* old = std::getenv("JACK_DEFAULT_SERVER");
    const std::string saved = old ? old : "";
    setenv("JACK_DEFAULT_SERVER", "sdfvj-no-such-server-7f3a", 1);
    std::string status;
    std::unique_ptr<AudioInput> in = AudioInput::Open(AudioInputDesc{}, &status);
    if (old) setenv("JACK_DEFAULT_SERVER", saved.c_str(), 1);
    else unsetenv("JACK_DEFAULT_SERVER");
    CHECK_FALSE(in);
    CHECK(status.rfind("audio: no JACK server 'sdfvj-no-such-server-7f3a'", 0) == 0);
    CHECK(status.find("the show goes on without audio") != std::string::npos);
    CHECK(status.find('\n') == std::string::npos);
}
