// MIDI port discovery (midi_ports.h) and `sdfvj list`'s port listing.
#include "control/midi_ports.h"

#include <jack/jack.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>

#include "control/control.h"

namespace sdfvj {

namespace {

void SilentJack(const char*) {}

std::string Lower(std::string s) {
    for (char& c : s) c = char(std::tolower((unsigned char)c));
    return s;
}

}  // namespace

bool IsIndex(const std::string& s) {
    return !s.empty() && s.size() < 6 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// True when a JACK server answers. Opening a client is the only reliable test
// (`jack_wait -c` exits 0 with no server).
bool JackServerRunning() {
    static bool silenced = [] {
        jack_set_error_function(SilentJack);
        jack_set_info_function(SilentJack);
        return true;
    }();
    (void)silenced;
    jack_status_t st;
    jack_client_t* c = jack_client_open("sdfvj-probe", JackNoStartServer, &st);
    if (!c) return false;
    jack_client_close(c);
    return true;
}

bool AlsaSequencerPresent() { return access("/dev/snd/seq", R_OK | W_OK) == 0; }

// Which of `names` the --midi option selects.
std::vector<std::string> SelectPorts(const std::vector<std::string>& names, const std::string& want) {
    std::vector<std::string> out;
    if (want.empty()) return names;
    if (IsIndex(want)) {
        size_t i = size_t(std::stoi(want));
        if (i < names.size()) out.push_back(names[i]);
        return out;
    }
    std::string w = Lower(want);
    for (const std::string& n : names)
        if (Lower(n).find(w) != std::string::npos) out.push_back(n);
    return out;
}

void QuietRtMidiError(RtMidiError::Type, const std::string&, void*) {}

std::vector<std::string> ListMidiPorts() {
    std::vector<std::string> out;
    try {
        RtMidi::Api api;
        if (JackServerRunning()) api = RtMidi::UNIX_JACK;
        else if (AlsaSequencerPresent()) api = RtMidi::LINUX_ALSA;
        else return out;
        RtMidiIn probe(api, "sdfvj-list");
        probe.setErrorCallback(QuietRtMidiError, nullptr);
        for (unsigned i = 0; i < probe.getPortCount(); ++i)
            out.push_back(std::to_string(i) + ": " + probe.getPortName(i));
    } catch (const std::exception&) {
    }
    return out;
}

}  // namespace sdfvj
