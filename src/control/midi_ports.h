// MIDI port discovery shared by the input session and `sdfvj list`: is a JACK server up, is
// there an ALSA sequencer, which ports does a --midi option select.
#pragma once

#include <rtmidi/RtMidi.h>

#include <string>
#include <vector>

namespace sdfvj {

// True when a JACK server answers (opening a client is the only reliable test).
bool JackServerRunning();
bool AlsaSequencerPresent();
// 1 to 5 decimal digits: a port index (--midi 2) or a UDP port (HOST:PORT).
bool IsIndex(const std::string& s);
// Which of `names` the --midi option `want` selects: all when empty, entry N for a number,
// else every name containing it (case-insensitive).
std::vector<std::string> SelectPorts(const std::vector<std::string>& names, const std::string& want);
// RtMidi's error callback that keeps RtMidi from printing (errors are reported as statuses).
void QuietRtMidiError(RtMidiError::Type, const std::string&, void*);

}  // namespace sdfvj
