// A test's fake MIDI device: a JACK client with one MIDI output port, written on libjack
// directly so that it can go away safely.
//
// RtMidi's MidiOutJack frees its ring buffers before it closes its JACK client, so a process
// callback that was already running reads freed memory: a rare SIGSEGV when a fake device is
// destroyed right after it sent (CI saw it in `midi reconnect`, `midi learn` and, after closing
// the port and sleeping a cycle first, still in `live_learn jack` on a loaded 2-core machine).
// Here the client is deactivated (JACK stops its process thread and joins it) before anything
// the callback reads is freed, and a port is unregistered only while the client is inactive.
//
// The subset of RtMidiOut the tests use, with the same meaning: getPortCount/getPortName list
// JACK's MIDI inputs, openPort(i) connects to one of them, openVirtualPort(name) makes a port
// that others connect to ("plug in"), closePort() removes it ("unplug"), sendMessage queues one
// message for the next JACK cycle. Errors throw std::runtime_error. Xruns() counts the cycles JACK
// reported late (a client that did not finish in time): events of such a cycle can be lost on
// the way, by JACK, before any of sdfvj's code sees them.
#pragma once
#include <jack/jack.h>
#include <jack/midiport.h>
#include <jack/ringbuffer.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace sdfvj::test {

class JackMidiOut {
public:
    explicit JackMidiOut(const std::string& clientName) {
        client_ = jack_client_open(clientName.c_str(), JackNoStartServer, nullptr);
        if (!client_) throw std::runtime_error("JackMidiOut: no JACK server for client '" + clientName + "'");
        ring_ = jack_ringbuffer_create(1 << 16);
        jack_set_process_callback(client_, &JackMidiOut::Process, this);
        jack_set_xrun_callback(client_, &JackMidiOut::Xrun, this);
        Activate();
    }
    ~JackMidiOut() {
        jack_deactivate(client_);   // returns once the process thread is out of Process
        jack_client_close(client_);
        jack_ringbuffer_free(ring_);
    }
    JackMidiOut(const JackMidiOut&) = delete;
    JackMidiOut& operator=(const JackMidiOut&) = delete;

    unsigned getPortCount() {
        inputs_.clear();
        const char** ports = jack_get_ports(client_, nullptr, JACK_DEFAULT_MIDI_TYPE, JackPortIsInput);
        for (const char** p = ports; p && *p; ++p) inputs_.push_back(*p);
        if (ports) jack_free(ports);
        return (unsigned)inputs_.size();
    }
    std::string getPortName(unsigned i) {
        if (i >= inputs_.size()) getPortCount();
        return i < inputs_.size() ? inputs_[i] : std::string();
    }
    // Registers an output named `portName` and connects it to input `i` of getPortCount's list.
    void openPort(unsigned i, const std::string& portName) {
        const std::string target = getPortName(i);
        if (target.empty()) throw std::runtime_error("JackMidiOut: no MIDI input " + std::to_string(i));
        openVirtualPort(portName);
        if (jack_connect(client_, jack_port_name(port_.load()), target.c_str()) != 0)
            throw std::runtime_error("JackMidiOut: cannot connect to " + target);
    }
    void openVirtualPort(const std::string& portName) {
        if (port_.load()) return;
        jack_port_t* p = jack_port_register(client_, portName.c_str(), JACK_DEFAULT_MIDI_TYPE, JackPortIsOutput, 0);
        if (!p) throw std::runtime_error("JackMidiOut: cannot register port " + portName);
        port_.store(p);
    }
    void closePort() {
        jack_port_t* p = port_.load();
        if (!p) return;
        jack_deactivate(client_);   // the callback is idle from here on: the port can go
        port_.store(nullptr);
        jack_port_unregister(client_, p);
        jack_ringbuffer_reset(ring_);
        Activate();
    }
    void sendMessage(const std::vector<unsigned char>* message) {
        if (!message || message->empty()) return;
        const uint32_t n = (uint32_t)message->size();
        if (jack_ringbuffer_write_space(ring_) < sizeof n + n) throw std::runtime_error("JackMidiOut: send queue full");
        jack_ringbuffer_write(ring_, reinterpret_cast<const char*>(&n), sizeof n);
        jack_ringbuffer_write(ring_, reinterpret_cast<const char*>(message->data()), n);
    }

    unsigned Xruns() const { return xruns_.load(); }

private:
    static int Xrun(void* arg) {
        ++static_cast<JackMidiOut*>(arg)->xruns_;
        return 0;
    }
    void Activate() {
        if (jack_activate(client_) != 0) throw std::runtime_error("JackMidiOut: cannot activate the JACK client");
    }
    // JACK's process thread: every queued message goes out at the start of this cycle.
    static int Process(jack_nframes_t frames, void* arg) {
        auto* self = static_cast<JackMidiOut*>(arg);
        jack_port_t* port = self->port_.load();
        if (!port) return 0;
        void* buffer = jack_port_get_buffer(port, frames);
        jack_midi_clear_buffer(buffer);
        uint32_t n = 0;
        while (jack_ringbuffer_peek(self->ring_, reinterpret_cast<char*>(&n), sizeof n) == sizeof n &&
               jack_ringbuffer_read_space(self->ring_) >= sizeof n + n) {
            jack_midi_data_t* out = jack_midi_event_reserve(buffer, 0, n);
            if (!out) break;   // the cycle's buffer is full: the rest goes out next cycle
            jack_ringbuffer_read_advance(self->ring_, sizeof n);
            jack_ringbuffer_read(self->ring_, reinterpret_cast<char*>(out), n);
        }
        return 0;
    }

    jack_client_t* client_ = nullptr;
    jack_ringbuffer_t* ring_ = nullptr;
    std::atomic<jack_port_t*> port_{nullptr};
    std::atomic<unsigned> xruns_{0};
    std::vector<std::string> inputs_;
};

using MidiOutPtr = std::unique_ptr<JackMidiOut>;

inline MidiOutPtr MakeMidiOut(const std::string& clientName) { return std::make_unique<JackMidiOut>(clientName); }

}  // namespace sdfvj::test
