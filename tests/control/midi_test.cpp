// MIDI end to end through JACK's dummy server (the `jackd` ctest fixture starts it): a fake device (jack_midi_out.h)
// on the JACK API sends into InputSession's ports; the tests assert the parameter values that
// come out of the mapping. Unique port names per process keep parallel runs apart.

#include "jack_midi_out.h"
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <thread>

#include <catch2/catch.hpp>

#include "automation/automation.h"
#include "test_util.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

std::string Unique(const char* base) { return std::string(base) + "-" + std::to_string(getpid()); }

// Opens a fake device connected to the first port whose name contains `needle`.
MidiOutPtr ConnectTo(const std::string& needle) {
    auto out = MakeMidiOut(Unique("midi-test"));
    for (unsigned i = 0; i < out->getPortCount(); ++i)
        if (out->getPortName(i).find(needle) != std::string::npos) {
            out->openPort(i, "out");
            return out;
        }
    FAIL("no JACK MIDI port contains '" << needle << "'");
    return nullptr;
}

void Send(JackMidiOut& out, std::vector<unsigned char> bytes) { out.sendMessage(&bytes); }

struct MidiRig {
    EventQueue queue;
    std::unique_ptr<InputSession> session;
    Mapping mapping;
    MappingState ms;
    ParamState params = MakeParamState(MidiSceneDecls());
    MappingActions acts;
    MidiRig(const std::string& midiPort, const std::string& virtualName) {
        InputOptions o;
        o.midiPort = midiPort;
        o.virtualPortName = virtualName;
        o.oscPort = -1;
        session = std::make_unique<InputSession>(o, queue, &Now);
    }
    // After a handshake of resent messages: waits until none has arrived for 200 ms, so a copy
    // still in flight is not counted as one of the messages that follow (under ASan on CI a copy
    // once landed more than 60 ms late and a frame was drawn before the notes it waited for).
    void Settle() {
        size_t last = queue.Pushed();
        auto quietSince = std::chrono::steady_clock::now();
        const auto end = quietSince + std::chrono::seconds(3);
        while (std::chrono::steady_clock::now() < end &&
               std::chrono::steady_clock::now() - quietSince < std::chrono::milliseconds(200)) {
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
            if (queue.Pushed() != last) last = queue.Pushed(), quietSince = std::chrono::steady_clock::now();
        }
    }
    bool Frame(size_t n) {
        bool ok = WaitFor([&] { return queue.Pushed() >= n; }, 3.0);
        for (const ControlEvent& e : queue.DrainUntil(Now())) ApplyEvent(mapping, ms, e, params, &acts);
        StepSmoothing(params, 1.0 / 60.0);
        return ok;
    }
};

}  // namespace

TEST_CASE("midi end to end: CC, 14-bit, NRPN, relative encoder and notes through JACK") {
    std::string vname = Unique("sdfvj-e2e");
    MidiRig r("no-controller-here", vname);
    bool jack = false;
    for (const std::string& s : r.session->StatusLines()) jack = jack || s.rfind("MIDI (JACK)", 0) == 0;
    INFO(r.session->StatusLines()[0]);
    REQUIRE(jack);
    REQUIRE(ParseMapping(R"(
[[map]]
cc = 1
target = "scale"
[[map]]
cc14 = 2
target = "twist"
[[map]]
nrpn = 300
target = "displacement"
[[map]]
cc = 16
encoder = "binary_offset"
step = 0.1
target = "smoothness"
[[pad]]
note = 36
action = "toggle"
target = "flag"
[[pad]]
note = 37
action = "effect"
effect = "shadows"
[[pad]]
note = 38
action = "preset"
preset = "intro"
)", "e2e.toml", &r.mapping).ok);

    auto out = ConnectTo(vname);
    // JACK connects asynchronously: resend a harmless message until the first one arrives.
    REQUIRE(WaitFor([&] { Send(*out, {0xB0, 1, 0}); return r.queue.Pushed() > 0; }, 3.0));
    r.Settle();   // the resent ones land first
    REQUIRE(r.Frame(1));
    size_t base = r.queue.Pushed();

    Send(*out, {0xB0, 1, 127});                                  // CC -> scale max
    Send(*out, {0xB0, 2, 64});                                   // 14-bit MSB
    Send(*out, {0xB0, 34, 0});                                   //        LSB
    Send(*out, {0xB0, 99, 2});                                   // NRPN 300 = 2 * 128 + 44
    Send(*out, {0xB0, 98, 44});
    Send(*out, {0xB0, 6, 100});
    Send(*out, {0xB0, 38, 5});
    Send(*out, {0xB0, 16, 67});                                  // encoder +3 ticks
    Send(*out, {0x90, 36, 100});                                 // toggle on
    Send(*out, {0x80, 36, 0});
    Send(*out, {0x90, 37, 100});                                 // effect toggle
    Send(*out, {0x90, 38, 100});                                 // preset
    REQUIRE(r.Frame(base + 12));
    CHECK(Param(r.params, "scale") == Approx(2.0f));
    CHECK(Param(r.params, "twist") == Approx(-3.0f + 6.0f * 8192 / 16383.0f));
    CHECK(Param(r.params, "displacement") == Approx((100 * 128 + 5) / 16383.0f));
    CHECK(Param(r.params, "smoothness") == Approx(0.25f));       // 0.2 + 3 * 0.1 of [0, 0.5]
    CHECK(Param(r.params, "flag") == 1.0f);
    CHECK(r.acts.effectToggles == std::vector<std::pair<std::string, bool>>{{"shadows", true}});
    CHECK(r.acts.presetSelect == std::vector<std::string>{"intro"});

    // SysEx and active sensing never reach the queue (RtMidi ignoreTypes); a clock pulse does
    // (the show's tempo follows it) but moves no parameter.
    base = r.queue.Pushed();
    Send(*out, {0xF0, 0x7E, 0x7F, 0x06, 0x01, 0xF7});
    Send(*out, {0xF8});
    Send(*out, {0xFE});
    REQUIRE(r.Frame(base + 1));
    CHECK(r.queue.Pushed() == base + 1);
    // Running status inside one JACK event, and a stray data byte.
    base = r.queue.Pushed();
    Send(*out, {0xB0, 1, 0, 16, 61});                            // scale min, encoder -3
    Send(*out, {0xF6, 0x05});                                    // tune request + a stray byte
    REQUIRE(r.Frame(base + 2));
    CHECK(r.queue.Pushed() == base + 2);
    CHECK(Param(r.params, "scale") == Approx(0.5f));
    CHECK(Param(r.params, "smoothness") == Approx(0.1f));
    REQUIRE(WaitFor([&] { return r.session->Counters().midiStray >= 1; }, 2.0));
    CHECK(r.session->Counters().midiStray == 1);
    // The smoothed value follows over frames, never jumps past the target.
    for (int i = 0; i < 120; ++i) StepSmoothing(r.params, 1.0 / 60.0);
    CHECK(r.params.value[FindParam(r.params, "scale")] == Approx(0.5f));
}

TEST_CASE("midi reconnect: a controller plugged in later and replugged is picked up within a second") {
    std::string dev = Unique("Fake LPD8");
    MidiRig r(dev, Unique("sdfvj-rc"));
    REQUIRE(ParseMapping("[[map]]\ncc = 1\ntarget = \"displacement\"\n", "t.toml", &r.mapping).ok);
    CHECK(r.session->StatusLines()[0].find("waiting for it") != std::string::npos);
    CHECK(r.session->OpenMidiPorts().empty());

    for (int round = 0; round < 2; ++round) {
        auto out = MakeMidiOut(Unique("fake-device"));
        out->openVirtualPort(dev);                                // "plug in"
        double plugged = Now();
        REQUIRE(WaitFor([&] { return !r.session->OpenMidiPorts().empty(); }, 1.0));
        double connectedAfter = Now() - plugged;
        CHECK(connectedAfter < 1.0);
        size_t base = r.queue.Pushed();
        REQUIRE(WaitFor([&] { Send(*out, {0xB0, 1, uint8_t(64 + round)}); return r.queue.Pushed() > base; }, 2.0));
        r.Frame(base + 1);
        CHECK(Param(r.params, "displacement") == Approx((64 + round) / 127.0f));
        out.reset();                                              // "unplug"
        REQUIRE(WaitFor([&] { return r.session->OpenMidiPorts().empty(); }, 1.0));
    }
}

TEST_CASE("midi list shows JACK ports, and a missing device is a status line") {
    std::string dev = Unique("Lister");
    MidiOutPtr outOwner = MakeMidiOut(Unique("lister-client"));
    JackMidiOut& out = *outOwner;
    out.openVirtualPort(dev);
    bool found = false;
    REQUIRE(WaitFor([&] {
        for (const std::string& p : ListMidiPorts()) found = found || p.find(dev) != std::string::npos;
        return found;
    }, 2.0));
    // Index selection: "--midi N" picks the N-th port of that list.
    std::vector<std::string> ports = ListMidiPorts();
    std::string index;
    for (const std::string& p : ports)
        if (p.find(dev) != std::string::npos) index = p.substr(0, p.find(':'));
    MidiRig r(index, Unique("sdfvj-idx"));
    REQUIRE(WaitFor([&] { return !r.session->OpenMidiPorts().empty(); }, 1.0));
    CHECK(r.session->OpenMidiPorts()[0].find(dev) != std::string::npos);
}

TEST_CASE("midi learn: the next control that moves is written to the mapping file") {
    std::string path = "/tmp/sdfvj-learn-" + std::to_string(getpid()) + ".toml";
    std::remove(path.c_str());
    int rc = -1;
    std::thread learner([&] { rc = RunLearn("twist", path, 5.0); });
    MidiOutPtr outOwner = MakeMidiOut(Unique("learn-client"));
    JackMidiOut& out = *outOwner;
    out.openVirtualPort(Unique("learn-src"));
    uint8_t v = 0;
    // A pad-like single value does not count; a knob sending different values does.
    WaitFor([&] { Send(out, {0xB2, 5, uint8_t(v++ % 2 ? 10 : 20)}); return rc != -1; }, 6.0);
    learner.join();
    REQUIRE(rc == 0);
    Mapping m;
    LoadResult r = LoadMapping(path, &m);
    INFO(r.error);
    REQUIRE(r.ok);
    REQUIRE(m.entries.size() == 1);
    CHECK(m.entries[0].kind == SourceKind::Cc);
    CHECK(m.entries[0].number == 5);
    CHECK(m.entries[0].channel == 3);
    CHECK(m.entries[0].target == "twist");
    std::remove(path.c_str());
}

TEST_CASE("midi learn: an NRPN control is learned as nrpn") {
    std::string path = "/tmp/sdfvj-learn-nrpn-" + std::to_string(getpid()) + ".toml";
    std::remove(path.c_str());
    int rc = -1;
    std::thread learner([&] { rc = RunLearn("displacement", path, 5.0); });
    MidiOutPtr outOwner = MakeMidiOut(Unique("learn-nrpn-client"));
    JackMidiOut& out = *outOwner;
    out.openVirtualPort(Unique("learn-nrpn-src"));
    WaitFor([&] {
        Send(out, {0xB0, 99, 3});
        Send(out, {0xB0, 98, 1});
        Send(out, {0xB0, 6, 50});
        return rc != -1;
    }, 6.0);
    learner.join();
    REQUIRE(rc == 0);
    Mapping m;
    REQUIRE(LoadMapping(path, &m).ok);
    REQUIRE(m.entries.size() == 1);
    CHECK(m.entries[0].kind == SourceKind::Nrpn);
    CHECK(m.entries[0].number == 3 * 128 + 1);
    std::remove(path.c_str());
}

TEST_CASE("midi replug: a controller port that vanishes and returns is heard again, and the status line says so") {
    // The stage case: the controller's cable is pulled and plugged back while the show runs.
    // Round 0 removes only the port (the client stays, as a driver that keeps running); round 1
    // closes the whole client (as a USB device that disappears with its driver).
    const std::string dev = Unique("test-controller");
    MidiRig r(dev, Unique("sdfvj-replug"));
    REQUIRE(ParseMapping("[[map]]\ncc = 1\ntarget = \"displacement\"\n", "t.toml", &r.mapping).ok);
    auto status = [&] { return r.session->StatusLines()[0]; };

    auto out = MakeMidiOut(Unique("soak-controller"));
    out->openVirtualPort(dev);
    // Sends value `v` until it arrives (JACK connects asynchronously after the next port poll).
    auto heard = [&](uint8_t v) {
        size_t base = r.queue.Pushed();
        if (!WaitFor([&] { Send(*out, {0xB0, 1, v}); return r.queue.Pushed() > base; }, 2.0)) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(30));   // resent copies land
        r.Frame(r.queue.Pushed());
        return Param(r.params, "displacement") == Approx(v / 127.0f);
    };
    REQUIRE(heard(10));
    INFO(status());
    CHECK(status().find("listening to") != std::string::npos);
    CHECK(status().find(dev) != std::string::npos);

    for (int round = 0; round < 2; ++round) {
        INFO("round " << round);
        if (round == 0) out->closePort();
        else out.reset();
        // The status line says the controller is gone, and names it, within two port polls.
        REQUIRE(WaitFor([&] { return status().find("gone") != std::string::npos; }, 1.0));
        INFO(status());
        CHECK(status().find(dev) != std::string::npos);
        CHECK(status().find("listening to") == std::string::npos);
        CHECK(r.session->OpenMidiPorts().empty());

        if (!out) out = MakeMidiOut(Unique("soak-controller"));
        out->openVirtualPort(dev);                                        // plugged back
        double plugged = Now();
        REQUIRE(WaitFor([&] { return !r.session->OpenMidiPorts().empty(); }, 1.0));
        CHECK(Now() - plugged < 1.0);
        REQUIRE(heard(uint8_t(40 + 30 * round)));
        INFO(status());
        CHECK(status().find("listening to") != std::string::npos);
        CHECK(status().find(dev) != std::string::npos);
        CHECK(status().find("gone") == std::string::npos);
    }
}

TEST_CASE("midi stalled server: a status read never waits for a JACK call the watcher is stuck in") {
    // The stage case behind a 1.3 s frame in the soak: the watcher thread's jack_connect to a
    // replugged controller waited on a busy JACK server while holding the session's lock, and the
    // frame's status read waited with it. A private server of this test's own is frozen
    // (SIGSTOP) right after a controller appears, so the watcher's jack_connect blocks until it
    // is thawed; every status read meanwhile must return at once.
    const std::string server = Unique("sdfvj-stall");
    // Started and stopped by the jackd fixture's own script, under this test's server name.
    const std::string fixture = std::string("sh ") + SDFVJ_JACKD_FIXTURE + " ", state = "/tmp/" + server;
    REQUIRE(std::system((fixture + "start " + state + " " + server + " >/dev/null").c_str()) == 0);
    std::ifstream pidFile(state + ".pid");
    pid_t jackd = 0;
    REQUIRE((pidFile >> jackd));
    struct Stop {
        std::string command, log;
        pid_t pid;
        ~Stop() { kill(pid, SIGCONT); (void)std::system(command.c_str()); std::remove(log.c_str()); }
    } stop{fixture + "stop " + state + " " + server + " >/dev/null", state + ".log", jackd};
    setenv("JACK_DEFAULT_SERVER", server.c_str(), 1);   // this process's clients use it

    const std::string dev = Unique("stall-controller");
    MidiRig r(dev, Unique("sdfvj-stall-in"));
    auto status = [&] { return r.session->StatusLines()[0]; };
    INFO(status());
    REQUIRE(status().rfind("MIDI (JACK)", 0) == 0);
    REQUIRE(status().find("listening to") == std::string::npos);

    auto out = MakeMidiOut(Unique("stall-device"));
    out->openVirtualPort(dev);   // registered: the server has answered
    REQUIRE(kill(jackd, SIGSTOP) == 0);
    const double frozen = Now();
    std::atomic<double> thawed{0.0};
    std::thread thaw([&] {   // its own thread: a status read that does wait cannot hang the test
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        kill(jackd, SIGCONT);
        thawed = Now();
    });
    double longest = 0.0, heardWhileFrozen = -1.0;
    while (Now() - frozen < 1.5) {   // a show's status reads, 200 a second
        const double t0 = Now();
        const std::string s = status();
        longest = std::max(longest, Now() - t0);
        if (heardWhileFrozen < 0.0 && thawed == 0.0 && s.find("listening to") != std::string::npos) heardWhileFrozen = Now() - frozen;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    thaw.join();
    // The watcher really was stuck: it connected the controller only once the server ran again.
    CHECK(heardWhileFrozen < 0.0);
    REQUIRE(WaitFor([&] { return status().find("listening to") != std::string::npos; }, 5.0));
    INFO("connected " << (Now() - thawed.load()) << " s after the thaw; longest status read " << longest * 1e3 << " ms");
    CHECK(status().find(dev) != std::string::npos);
    CHECK(longest < 0.1);
    // And the controller is heard through the connection made after the thaw. This also lets the
    // thawed server run steady cycles before the clients close: CI once crashed (SIGSEGV) in the
    // teardown right after the checks above, where, is not known (support/crash_trace.cpp prints
    // the stack if it happens again).
    const size_t base = r.queue.Pushed();
    CHECK(WaitFor([&] { Send(*out, {0xB0, 1, 64}); return r.queue.Pushed() > base; }, 2.0));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));   // resent copies land
}

TEST_CASE("midi clock: start, 24 pulses a beat and stop through JACK reach the queue and set the tempo") {
    std::string vname = Unique("sdfvj-clock");
    MidiRig r("no-controller-here", vname);
    auto out = ConnectTo(vname);
    REQUIRE(out);
    // JACK connects asynchronously (slowly on a loaded CI machine): resend a harmless CC until
    // one arrives, let the resent ones land, then count from there.
    REQUIRE(WaitFor([&] { Send(*out, {0xB0, 1, 0}); return r.queue.Pushed() > 0; }, 3.0));
    const int pulses = 48;   // two beats at 120 bpm
    // A take: start, the pulses, stop. Every event must arrive. The one excuse is JACK's own:
    // under ASan on a loaded 2-core CI machine a client once missed its cycle and two of the 50
    // events never reached any of sdfvj's code. Such a take is played again, only when JACK
    // reported the late cycle (an xrun) during it; a take short with no xrun fails the test.
    std::vector<ControlEvent> take;
    for (int attempt = 1;; ++attempt) {
        r.Settle();
        r.queue.DrainUntil(Now() + 1e9);   // the handshake and any earlier take
        const size_t base = r.queue.Pushed();
        const unsigned xruns = out->Xruns();
        Send(*out, {0xFA});
        for (int i = 0; i < pulses; ++i) {
            Send(*out, {0xF8});
            std::this_thread::sleep_for(std::chrono::microseconds(20833));
        }
        Send(*out, {0xFC});
        const bool whole = WaitFor([&] { return r.queue.Pushed() >= base + pulses + 2; }, 3.0);
        const unsigned late = out->Xruns() - xruns;
        INFO("take " << attempt << ": events pushed " << r.queue.Pushed() - base << " of " << pulses + 2
                     << "; JACK reported " << late << " late cycle(s) during it");
        if (whole) {
            take = r.queue.DrainUntil(Now());
            break;
        }
        REQUIRE(late > 0);
        REQUIRE(attempt < 3);
        WARN("JACK lost events in a late cycle; the take is played again");
    }
    TempoState tempo;
    tempo.bpm = 60.0;
    MidiClockFollower clock;
    int seen = 0, starts = 0, stops = 0;
    for (const ControlEvent& e : take) {
        if (e.midiSize == 1 && e.midi[0] == 0xF8) ++seen;
        if (e.midiSize == 1 && e.midi[0] == 0xFA) ++starts;
        if (e.midiSize == 1 && e.midi[0] == 0xFC) ++stops;
        clock.OnEvent(e, tempo);
    }
    CHECK(seen == pulses);
    CHECK(starts == 1);
    CHECK(stops == 1);
    INFO("tempo from the pulses: " << tempo.bpm << " bpm");
    CHECK(tempo.bpm > 100.0);   // JACK delivers in 5.3 ms periods: the median gap is near 20.8 ms
    CHECK(tempo.bpm < 145.0);
    CHECK_FALSE(tempo.running);
    CHECK(tempo.Beats(Now() + 10.0) == Approx(tempo.Beats(Now())));
}
