// InputSession: RtMidi ports, the liblo server thread, and a watcher thread.
//
// Threads and what they may touch:
//   - RtMidi callback (JACK process thread or ALSA thread): its port's MidiDecoder, the queue,
//     the atomic counters. Nothing else.
//   - liblo server thread: DecodeOscMessage, the queue, the counters, `lastOscProblem` (mutex).
//   - watcher thread: Poll() every 250 ms (port list, connections) and the once-a-second log.
//   - caller (render thread): StatusLines(), OpenMidiPorts(), SendFeedback(). These read a copy
//     published under `shownMutex`, never `mutex`: the watcher holds `mutex` across JACK calls
//     (jack_get_ports, jack_connect), which wait on the JACK server and took 1.3 s once while a
//     controller was replugged under load; a frame must not wait with them.
// On JACK there is one input port (the virtual port, `sdfvj:sdfvj`); hardware and software
// sources are connected to it with jack_connect, so a source is never heard twice and a
// replugged controller is reconnected at the next poll. On ALSA each source gets its own
// RtMidiIn. Neither available: a status line, and OSC still works.
#include <jack/jack.h>
#include <lo/lo.h>
#include <rtmidi/RtMidi.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <set>
#include <thread>

#include "control/control.h"
#include "control/midi_ports.h"

namespace sdfvj {

namespace {

thread_local InputSession::Impl* tlOscSession = nullptr;  // set on the liblo thread at start
thread_local std::string tlOscCreateError;                 // liblo errors while creating the server

}  // namespace

struct MidiPort {
    InputSession::Impl* owner = nullptr;
    std::string name;
    MidiDecoder decoder;   // touched only by this port's callback thread
    // Last, so it goes first: its callback (which uses the members above) has stopped before
    // they are destroyed.
    std::unique_ptr<RtMidiIn> in;
};

struct InputSession::Impl {
    InputOptions opt;
    EventQueue& queue;
    std::function<double()> clock;
    InputCounters counters;

    // MIDI (watcher thread + constructor/destructor; `mutex` guards them against Poll()).
    mutable std::mutex mutex;
    enum class Api { None, Jack, Alsa } api = Api::None;
    jack_client_t* jackControl = nullptr;          // for the port list and jack_connect
    // Set by JACK's shutdown callback. On the heap, apart from the session: a client abandoned
    // after its server died (AbandonDeadJack) keeps its callback, which may still be called after
    // the session is gone, so the flag it writes is abandoned with it.
    std::atomic<bool>* jackDied = nullptr;
    bool JackDied() const { return jackDied && jackDied->load(); }
    std::unique_ptr<MidiPort> virtualIn;
    std::string virtualFullName;                   // "sdfvj:sdfvj" on JACK
    std::vector<std::unique_ptr<MidiPort>> alsaPorts;
    std::unique_ptr<RtMidiIn> alsaProbe;           // kept: one sequencer client for the port list
    std::vector<std::string> connected;            // sources we listen to
    std::vector<std::string> gone;                 // sources we listened to that vanished (unplugged)
    std::string midiStatus;
    int pollsWithoutMidi = 0;

    // What the render thread reads: copies of midiStatus, connected and oscStatus, published by
    // whoever holds `mutex` after it changed them (Publish), guarded by this lock alone.
    mutable std::mutex shownMutex;
    std::string shownMidi, shownOsc;
    std::vector<std::string> shownConnected;

    // Caller holds `mutex`.
    void Publish() {
        std::lock_guard<std::mutex> g(shownMutex);
        shownMidi = midiStatus;
        shownOsc = oscStatus;
        shownConnected = connected;
    }

    // OSC.
    lo_server_thread osc = nullptr;
    int oscPort = -1;
    std::string oscStatus;
    lo_address feedback = nullptr;
    std::mutex problemMutex;
    std::string lastOscProblem;

    // Watcher.
    std::thread watcher;
    std::mutex watchMutex;
    std::condition_variable watchCv;
    bool stopping = false;

    Impl(const InputOptions& o, EventQueue& q, std::function<double()> c) : opt(o), queue(q), clock(std::move(c)) {}

    static void OnMidi(double, std::vector<unsigned char>* msg, void* user) {
        auto* port = static_cast<MidiPort*>(user);
        Impl* s = port->owner;
        if (!s || !msg || msg->empty()) return;
        MidiDecoder& d = port->decoder;
        uint64_t stray = d.stray, ignored = d.ignored;
        std::vector<ControlEvent> events;
        events.reserve(2);
        DecodeMidiBytes(d, msg->data(), msg->size(), s->clock(), &events);
        s->counters.midiStray += d.stray - stray;
        s->counters.midiIgnored += d.ignored - ignored;
        s->counters.midiMessages += events.size();
        for (ControlEvent& e : events) s->queue.Push(std::move(e));
    }

    std::unique_ptr<MidiPort> MakePort(RtMidi::Api rtApi, const std::string& client) {
        auto p = std::make_unique<MidiPort>();
        p->owner = this;
        p->in = std::make_unique<RtMidiIn>(rtApi, client, 1024);
        p->in->setErrorCallback(QuietRtMidiError, nullptr);
        p->in->ignoreTypes(false, false, true);   // active sensing never reaches us; MIDI clock does (tempo), SysEx too (MTC full frames; others are counted as ignored)
        p->in->setCallback(&Impl::OnMidi, p.get());
        return p;
    }

    std::vector<std::string> JackSources() {
        std::vector<std::string> out;
        const char** ports = jack_get_ports(jackControl, nullptr, JACK_DEFAULT_MIDI_TYPE, JackPortIsOutput);
        for (const char** p = ports; p && *p; ++p) out.push_back(*p);
        if (ports) jack_free(ports);
        return out;
    }

    std::set<std::string> JackInputs() {
        std::set<std::string> out;
        const char** ports = jack_get_ports(jackControl, nullptr, JACK_DEFAULT_MIDI_TYPE, JackPortIsInput);
        for (const char** p = ports; p && *p; ++p) out.insert(*p);
        if (ports) jack_free(ports);
        return out;
    }

    void StartMidi() {
        if (!opt.midi) {
            midiStatus = "MIDI: off";
            return;
        }
        try {
            if (JackServerRunning()) {
                jack_status_t st;
                jackControl = jack_client_open("sdfvj-control", JackNoStartServer, &st);
                if (!jackControl) throw std::runtime_error("cannot open a JACK client");
                jackDied = new std::atomic<bool>(false);
                jack_on_shutdown(jackControl, [](void* u) { static_cast<std::atomic<bool>*>(u)->store(true); }, jackDied);
                jack_activate(jackControl);
                std::set<std::string> before = JackInputs();
                virtualIn = MakePort(RtMidi::UNIX_JACK, opt.virtualPortName);
                virtualIn->in->openVirtualPort(opt.virtualPortName);
                for (const std::string& n : JackInputs())
                    if (!before.count(n) && n.size() > opt.virtualPortName.size() &&
                        n.compare(n.size() - opt.virtualPortName.size() - 1, std::string::npos, ":" + opt.virtualPortName) == 0)
                        virtualFullName = n;
                if (virtualFullName.empty()) throw std::runtime_error("virtual port did not appear in JACK");
                virtualIn->name = virtualFullName;
                api = Api::Jack;
            } else if (AlsaSequencerPresent()) {
                if (opt.virtualPort) {
                    virtualIn = MakePort(RtMidi::LINUX_ALSA, "sdfvj");
                    virtualIn->in->openVirtualPort(opt.virtualPortName);
                    virtualIn->name = opt.virtualPortName;
                }
                api = Api::Alsa;
            } else {
                api = Api::None;
                midiStatus = "MIDI: no JACK server and no ALSA sequencer, no controller (OSC still works)";
                return;
            }
        } catch (const std::exception& e) {
            api = Api::None;
            virtualIn.reset();
            CloseJackControl();
            midiStatus = std::string("MIDI: unavailable (") + e.what() + ")";
            return;
        }
        Reconnect();
    }

    // Caller holds `mutex`. Runs on the watcher thread, so nothing may escape it.
    void Reconnect() {
        try {
            ReconnectOrThrow();
        } catch (const std::exception& e) {
            midiStatus = std::string("MIDI: port scan failed (") + e.what() + ")";
        }
    }

    // A live client: closed, and its shutdown flag with it.
    void CloseJackControl() {
        if (jackControl) jack_client_close(jackControl);
        jackControl = nullptr;
        delete jackDied;
        jackDied = nullptr;
    }

    // After the JACK server went away, closing a port or client crashes inside libjack, so the
    // dead RtMidiIn and client are abandoned (a few KB) and MIDI waits for a server again.
    void AbandonDeadJack() {
        if (virtualIn) virtualIn->owner = nullptr;   // its callback, if ever called again, does nothing
        (void)virtualIn.release();
        jackControl = nullptr;
        jackDied = nullptr;                          // abandoned with the client whose callback writes it
        connected.clear();
        api = Api::None;
        midiStatus = "MIDI: the JACK server stopped; waiting for it to come back";
        if (opt.log) std::fprintf(stderr, "sdfvj: %s\n", midiStatus.c_str());
    }

    // Caller holds `mutex`. Sources listened to at the last poll and missing now join `gone`;
    // one that is listened to again leaves it. Bounded: a studio of hot-plugged gear keeps the
    // last few names only.
    void NoteGone(const std::vector<std::string>& before) {
        auto has = [](const std::vector<std::string>& v, const std::string& n) { return std::find(v.begin(), v.end(), n) != v.end(); };
        gone.erase(std::remove_if(gone.begin(), gone.end(), [&](const std::string& n) { return has(connected, n); }), gone.end());
        for (const std::string& n : before)
            if (!has(connected, n) && !has(gone, n)) gone.push_back(n);
        if (gone.size() > 4) gone.erase(gone.begin(), gone.end() - 4);
    }

    void ReconnectOrThrow() {
        if (api == Api::Jack && JackDied()) AbandonDeadJack();
        if (api == Api::None) {
            // A JACK server that came up after us: look once a second.
            if (opt.midi && ++pollsWithoutMidi % 4 == 0 && JackServerRunning()) StartMidi();
            return;
        }
        const std::vector<std::string> before = connected;
        std::vector<std::string> wanted;
        if (api == Api::Jack) {
            wanted = SelectPorts(JackSources(), opt.midiPort);
            jack_port_t* mine = jack_port_by_name(jackControl, virtualFullName.c_str());
            connected.clear();
            for (const std::string& src : wanted) {
                if (mine && !jack_port_connected_to(mine, src.c_str())) jack_connect(jackControl, src.c_str(), virtualFullName.c_str());
                connected.push_back(src);
            }
        } else {
            if (!alsaProbe) {
                alsaProbe = std::make_unique<RtMidiIn>(RtMidi::LINUX_ALSA, "sdfvj-probe");
                alsaProbe->setErrorCallback(QuietRtMidiError, nullptr);
            }
            std::vector<std::string> names;
            for (unsigned i = 0; i < alsaProbe->getPortCount(); ++i) names.push_back(alsaProbe->getPortName(i));
            // Select first (so "--midi 2" means entry 2 of `sdfvj list`), then never listen to
            // our own virtual port through the sequencer as well.
            wanted = SelectPorts(names, opt.midiPort);
            wanted.erase(std::remove_if(wanted.begin(), wanted.end(), [&](const std::string& n) {
                             return virtualIn && n.find(opt.virtualPortName) != std::string::npos;
                         }), wanted.end());
            alsaPorts.erase(std::remove_if(alsaPorts.begin(), alsaPorts.end(), [&](const auto& p) {
                                return std::find(wanted.begin(), wanted.end(), p->name) == wanted.end();
                            }), alsaPorts.end());
            for (const std::string& w : wanted) {
                bool open = std::any_of(alsaPorts.begin(), alsaPorts.end(), [&](const auto& p) { return p->name == w; });
                if (open) continue;
                for (unsigned i = 0; i < names.size(); ++i) {
                    if (names[i] != w) continue;
                    try {
                        auto p = MakePort(RtMidi::LINUX_ALSA, "sdfvj-in");
                        p->in->openPort(i, "in");
                        p->name = w;
                        alsaPorts.push_back(std::move(p));
                    } catch (const std::exception&) {
                    }
                }
            }
            connected.clear();
            for (auto& p : alsaPorts) connected.push_back(p->name);
        }
        NoteGone(before);
        std::string apiName = api == Api::Jack ? "JACK" : "ALSA";
        std::string s = "MIDI (" + apiName + "): ";
        if (virtualIn) s += "virtual port " + virtualIn->name + "; ";
        if (!connected.empty()) {
            s += "listening to ";
            for (size_t i = 0; i < connected.size(); ++i) s += (i ? ", " : "") + connected[i];
            if (!gone.empty()) s += "; ";
        }
        if (!gone.empty()) {
            // A controller that was unplugged: say so until it is back (then it is listened to
            // again at the next poll, no restart needed).
            for (size_t i = 0; i < gone.size(); ++i) s += (i ? ", " : "") + gone[i];
            s += gone.size() == 1 ? " is gone (unplugged?), waiting for it to come back"
                                  : " are gone (unplugged?), waiting for them to come back";
        } else if (connected.empty()) {
            s += opt.midiPort.empty() ? "no controller connected"
                                      : "no port matches '" + opt.midiPort + "', waiting for it";
        }
        if (s != midiStatus && opt.log) std::fprintf(stderr, "sdfvj: %s\n", s.c_str());
        midiStatus = s;
    }

    static void OnOscError(int num, const char* msg, const char* where) {
        if (Impl* s = tlOscSession) {
            s->counters.oscMalformed++;
            std::lock_guard<std::mutex> lock(s->problemMutex);
            s->lastOscProblem = std::string(msg ? msg : "error") + " (" + std::to_string(num) + ")" +
                                (where ? std::string(" at ") + where : "");
        } else {
            tlOscCreateError = std::string(msg ? msg : "error") + (where ? std::string(" ") + where : "");
        }
    }

    // The body is HandleOscMessage (decode.cpp), which the fuzzer drives through a real lo_server.
    static int OnOsc(const char* path, const char* types, lo_arg** argv, int argc, lo_message, void* user) {
        auto* s = static_cast<Impl*>(user);
        std::string why;
        if (!HandleOscMessage(path, types, reinterpret_cast<const void* const*>(argv), argc, s->clock(), s->queue,
                              s->counters, &why)) {
            std::lock_guard<std::mutex> lock(s->problemMutex);
            s->lastOscProblem = why;
        }
        return 0;
    }

    void StartOsc() {
        if (opt.oscPort < 0) {
            oscStatus = "OSC: off";
            return;
        }
        std::string port = std::to_string(opt.oscPort);
        tlOscCreateError.clear();
        osc = lo_server_thread_new_with_proto(opt.oscPort == 0 ? nullptr : port.c_str(), LO_UDP, &Impl::OnOscError);
        if (!osc) {
            oscStatus = "OSC: cannot listen on UDP port " + port + " (" + tlOscCreateError + "), OSC is off";
            return;
        }
        lo_server_thread_set_callbacks(
            osc, [](lo_server_thread, void* u) { tlOscSession = static_cast<Impl*>(u); return 0; },
            [](lo_server_thread, void*) { tlOscSession = nullptr; }, this);
        lo_server_thread_add_method(osc, nullptr, nullptr, &Impl::OnOsc, this);
        // Bundles are dispatched at once, whatever their timetag: liblo's queue for future ones
        // grows without bound and inserts in O(n), so a flood of them stalled this thread.
        lo_server_enable_queue(lo_server_thread_get_server(osc), 0, 1);
        if (lo_server_thread_start(osc) != 0) {
            lo_server_thread_free(osc);
            osc = nullptr;
            oscStatus = "OSC: server thread did not start, OSC is off";
            return;
        }
        oscPort = lo_server_thread_get_port(osc);
        oscStatus = "OSC: listening on UDP port " + std::to_string(oscPort);
        if (!opt.oscFeedback.empty()) {
            size_t colon = opt.oscFeedback.rfind(':');
            if (colon == std::string::npos || colon == 0 || !IsIndex(opt.oscFeedback.substr(colon + 1))) {
                oscStatus += "; feedback target '" + opt.oscFeedback + "' is not HOST:PORT, no feedback";
            } else {
                feedback = lo_address_new(opt.oscFeedback.substr(0, colon).c_str(), opt.oscFeedback.substr(colon + 1).c_str());
                oscStatus += feedback ? "; feedback to " + opt.oscFeedback : "; cannot resolve " + opt.oscFeedback;
            }
        }
        if (opt.log) std::fprintf(stderr, "sdfvj: %s\n", oscStatus.c_str());
    }

    void Watch() {
        using namespace std::chrono;
        auto lastLog = steady_clock::now();
        uint64_t seen[5] = {0, 0, 0, 0, 0};
        std::unique_lock<std::mutex> lock(watchMutex);
        while (!stopping) {
            watchCv.wait_for(lock, milliseconds(250));
            if (stopping) break;
            lock.unlock();
            {
                std::lock_guard<std::mutex> g(mutex);
                Reconnect();
                Publish();
            }
            auto now = steady_clock::now();
            if (opt.log && duration<double>(now - lastLog).count() >= opt.logInterval) {
                uint64_t cur[5] = {counters.oscMalformed, counters.oscWrongType, counters.midiStray,
                                   counters.midiIgnored, queue.Dropped()};
                if (!std::equal(cur, cur + 5, seen)) {
                    std::string last;
                    {
                        std::lock_guard<std::mutex> g(problemMutex);
                        last = lastOscProblem;
                    }
                    std::fprintf(stderr,
                                 "sdfvj: bad input in the last %.0f s: %llu malformed OSC packets, %llu OSC "
                                 "messages with wrong types, %llu stray MIDI bytes, %llu ignored MIDI bytes, "
                                 "%llu events dropped%s%s\n",
                                 opt.logInterval, (unsigned long long)(cur[0] - seen[0]),
                                 (unsigned long long)(cur[1] - seen[1]), (unsigned long long)(cur[2] - seen[2]),
                                 (unsigned long long)(cur[3] - seen[3]), (unsigned long long)(cur[4] - seen[4]),
                                 last.empty() ? "" : "; last OSC problem: ", last.c_str());
                    std::copy(cur, cur + 5, seen);
                }
                lastLog = now;
            }
            lock.lock();
        }
    }
};

InputSession::InputSession(const InputOptions& opt, EventQueue& queue, std::function<double()> clock)
    : impl_(std::make_unique<Impl>(opt, queue, std::move(clock))) {
    std::lock_guard<std::mutex> g(impl_->mutex);
    impl_->StartMidi();
    impl_->StartOsc();
    impl_->Publish();
    impl_->watcher = std::thread([this] { impl_->Watch(); });
}

InputSession::~InputSession() {
    {
        std::lock_guard<std::mutex> g(impl_->watchMutex);
        impl_->stopping = true;
    }
    impl_->watchCv.notify_all();
    if (impl_->watcher.joinable()) impl_->watcher.join();
    if (impl_->osc) lo_server_thread_free(impl_->osc);   // stops and joins the liblo thread
    if (impl_->feedback) lo_address_free(impl_->feedback);
    std::lock_guard<std::mutex> g(impl_->mutex);
    if (impl_->api == Impl::Api::Jack && impl_->JackDied()) impl_->AbandonDeadJack();
    impl_->alsaPorts.clear();
    impl_->alsaProbe.reset();
    impl_->virtualIn.reset();
    impl_->CloseJackControl();
}

std::vector<std::string> InputSession::StatusLines() const {
    std::lock_guard<std::mutex> g(impl_->shownMutex);
    return {impl_->shownMidi, impl_->shownOsc};
}

int InputSession::OscPort() const { return impl_->oscPort; }

void InputSession::Poll() {
    std::lock_guard<std::mutex> g(impl_->mutex);
    impl_->Reconnect();
    impl_->Publish();
}

std::vector<std::string> InputSession::OpenMidiPorts() const {
    std::lock_guard<std::mutex> g(impl_->shownMutex);
    return impl_->shownConnected;
}

const InputCounters& InputSession::Counters() const { return impl_->counters; }

void InputSession::SendFeedback(const ParamState& params, const std::string& presetName) {
    if (!impl_->feedback) return;
    for (size_t i = 0; i < params.decls.size(); ++i) {
        const ParamDecl& d = params.decls[i];
        float range = d.maxValue - d.minValue;
        float x = range != 0.0f ? (params.target[i] - d.minValue) / range : 0.0f;
        lo_send(impl_->feedback, ("/sdfvj/param/" + d.name).c_str(), "f", x);
    }
    if (!presetName.empty()) lo_send(impl_->feedback, "/sdfvj/preset", "s", presetName.c_str());
}

}  // namespace sdfvj
