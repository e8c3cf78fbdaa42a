// A test's fake MIDI device (RtMidiOut on JACK) that goes away safely.
//
// RtMidi 4.0's MidiOutJack destructor frees its ring buffers before it closes its JACK client,
// so a process callback running in between reads freed memory: a rare SIGSEGV when a fake device
// is destroyed right after it sent (CI saw it in `midi reconnect` and `midi learn` under ctest -j).
// The callback returns at once when the port is gone, so: close the port, let a JACK cycle pass,
// then delete.
#pragma once
#include <rtmidi/RtMidi.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>

namespace sdfvj::test {

struct MidiOutDeleter {
    void operator()(RtMidiOut* out) const {
        if (!out) return;
        out->closePort();
        std::this_thread::sleep_for(std::chrono::milliseconds(40));   // > one JACK cycle (512 / 48 kHz)
        delete out;
    }
};
using MidiOutPtr = std::unique_ptr<RtMidiOut, MidiOutDeleter>;

inline MidiOutPtr MakeMidiOut(const std::string& clientName) {
    return MidiOutPtr(new RtMidiOut(RtMidi::UNIX_JACK, clientName));
}

}  // namespace sdfvj::test
