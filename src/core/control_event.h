// ControlEvent: the one thing input threads hand to the render thread.
//
// MIDI (RtMidi callback), OSC (liblo server thread) and replay (.mid reader) all produce
// ControlEvents with a timestamp on the session clock; nothing else happens on those threads.
// The render thread drains them up to each frame's start time and maps them to parameters.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace sdfvj {

// One OSC argument. Only the types sdfvj acts on are decoded; others keep their tag.
struct OscArg {
    char type = 'f';     // 'f' float, 'i' int32, 's' string, other tags are kept but ignored
    float f = 0.0f;
    int32_t i = 0;
    std::string s;
};

enum class EventSource : uint8_t { Midi, Osc };

struct ControlEvent {
    double time = 0.0;                   // seconds on the session clock (wall or replay)
    EventSource source = EventSource::Midi;
    // MIDI: one complete short message (status byte first, running status already resolved).
    uint8_t midi[3] = {0, 0, 0};
    uint8_t midiSize = 0;
    // OSC: address and arguments.
    std::string address;
    std::vector<OscArg> args;
};

}  // namespace sdfvj
