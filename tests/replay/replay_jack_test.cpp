// A recording made through the real MIDI path replays to the same parameter values.
//
// Live side, in this process: JACK's dummy server (ctest fixture `jackd`), InputSession with its
// virtual JACK port, EventQueue, the generic mapping, smoothing, and a TakeRecorder that records
// every drained event, on a fixed 60 fps frame clock of its own (frame k starts at t0 + k/60; it
// drains the events stamped up to that time). A fake device on JACK (jack_midi_out.h) sends 48 CCs on the
// four knobs with uneven sleeps from another thread.
// Replay side: ReadTake + MakeReplayDriver on the recorded file, at the same frame times.
//
// Tolerance: the file stores times on a 0.5 ms grid, so an event stamped within 0.25 ms before a
// frame start can move to the next frame. The test works out, for every event, which frame live
// and replay applied it to. When they agree everywhere (the usual case), every parameter must
// match at every frame (to 1e-6); when one slipped, the frames before the first slip must match
// and the final values (0.5 s after the last event) must agree to 1e-4.

#include "../control/jack_midi_out.h"
using sdfvj::test::MakeMidiOut;
using sdfvj::test::MidiOutPtr;
using sdfvj::test::JackMidiOut;
#include <unistd.h>

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <thread>

#include "app/live_support.h"
#include "app/replay_driver.h"
#include "control/control.h"
#include "take/take.h"

using namespace sdfvj;
namespace fs = std::filesystem;

namespace {

double Now() {
    static const auto t0 = std::chrono::steady_clock::now();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void SleepUntil(double t) {
    while (Now() < t) std::this_thread::sleep_for(std::chrono::microseconds(200));
}

}  // namespace

TEST_CASE("replay of a take recorded through JACK gives the live run's parameter values") {
    const std::string vname = "sdfvj-replay-" + std::to_string(getpid());
    ShowOptions opts;
    opts.scene = "midi";
    Show show;
    std::string error;
    REQUIRE(PrepareShow(opts, &show, &error));
    Mapping mapping;
    REQUIRE(LoadShowMapping(show, "mappings/generic_8knob.toml", &mapping, &error));

    EventQueue queue;
    InputOptions io;
    io.midiPort = "no-controller-here";
    io.virtualPortName = vname;
    io.oscPort = -1;
    io.log = false;
    InputSession session(io, queue, &Now);
    bool jack = false;
    for (const std::string& s : session.StatusLines()) jack = jack || s.rfind("MIDI (JACK)", 0) == 0;
    INFO(session.StatusLines()[0]);
    REQUIRE(jack);

    MidiOutPtr outOwner = MakeMidiOut("replay-test-out-" + std::to_string(getpid()));

    JackMidiOut& out = *outOwner;
    bool connected = false;
    for (unsigned i = 0; i < out.getPortCount() && !connected; ++i)
        if (out.getPortName(i).find(vname) != std::string::npos) {
            out.openPort(i, "out");
            connected = true;
        }
    REQUIRE(connected);
    // JACK finishes the connection on its own thread: a message sent before that is lost (one of
    // the 48 was, once, in a CI run that started this test beside jackd and Xvfb). So a probe goes
    // through first, again until one arrives, and is drained before the take begins.
    bool through = false;
    for (int attempt = 0; attempt < 40 && !through; ++attempt) {
        std::vector<unsigned char> probe = {0xB0, 119, 0};   // CC 119: no knob of the mapping
        out.sendMessage(&probe);
        const double until = Now() + 0.05;
        while (Now() < until && queue.Size() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        through = queue.Size() > 0;
    }
    REQUIRE(through);
    std::this_thread::sleep_for(std::chrono::milliseconds(60));   // probes still in flight land now
    queue.DrainUntil(Now());
    REQUIRE(queue.Size() == 0);

    const std::string take = std::string(SDFVJ_REPLAY_OUT) + "/jack_take.mid";
    fs::create_directories(SDFVJ_REPLAY_OUT);
    const double t0 = Now() + 0.02;
    TakeRecorder rec;
    TakeRecorderDesc desc;
    desc.timeOrigin = t0;
    REQUIRE(rec.Open(take, desc, &error));

    // 48 CCs on knobs 1-4 (CC 20-23) over ~0.9 s, uneven gaps, starting 0.1 s in.
    constexpr int kMessages = 48;
    std::thread sender([&] {
        SleepUntil(t0 + 0.1);
        for (int i = 0; i < kMessages; ++i) {
            std::vector<unsigned char> m = {0xB0, (unsigned char)(20 + i % 4), (unsigned char)((i * 37 + 11) % 128)};
            out.sendMessage(&m);
            std::this_thread::sleep_for(std::chrono::microseconds(4000 + (i * 7919) % 29000));
        }
    });

    // Live: 60 fps on its own clock, 2 s.
    const int kFrames = 120;
    const double dt = 1.0 / 60.0;
    MappingState ms;
    ParamState params = ShowParamState(show);
    std::vector<std::vector<std::pair<std::string, float>>> live(kFrames);
    std::vector<int> liveFrameOf;   // per drained event, in order: the frame it was applied to
    for (int k = 0; k < kFrames; ++k) {
        const double frameStart = t0 + k * dt;
        SleepUntil(frameStart);
        for (const ControlEvent& e : queue.DrainUntil(frameStart)) {
            rec.Record(e);
            liveFrameOf.push_back(k);
            ApplyEvent(mapping, ms, e, params, nullptr);
        }
        StepSmoothing(params, dt);
        CopyParams(params, &live[k]);
    }
    sender.join();
    rec.Close(t0 + kFrames * dt);
    REQUIRE(queue.Size() == 0);
    REQUIRE(liveFrameOf.size() == (size_t)kMessages);   // every CC arrived within the 2 s
    CHECK(rec.Dropped() == 0);

    // Replay.
    Take t;
    TakeReadResult r = ReadTake(take, &t);
    INFO(r.error);
    REQUIRE(r.ok);
    REQUIRE(t.events.size() == (size_t)kMessages);
    int firstSlip = kFrames, slips = 0;
    for (size_t i = 0; i < t.events.size(); ++i) {
        CHECK(t.events[i].midi[0] == 0xB0);
        CHECK(t.events[i].midi[1] == 20 + i % 4);
        CHECK(t.events[i].midi[2] == (i * 37 + 11) % 128);
        int k = 0;   // the replay driver applies an event to the first frame with start > time - 1e-9
        while (!(t.events[i].time < k * dt + 1e-9)) ++k;
        if (k != liveFrameOf[i]) {
            ++slips;
            firstSlip = std::min(firstSlip, std::min(k, liveFrameOf[i]));
            WARN("event " << i << " at " << t.events[i].time << " s: live frame " << liveFrameOf[i] << ", replay frame " << k
                          << " (within the 0.5 ms tick of a frame start)");
        }
    }
    auto driver = MakeReplayDriver(show, take, "mappings/generic_8knob.toml", &error);
    INFO(error);
    REQUIRE(driver);
    std::vector<std::pair<std::string, float>> values;
    int compared = 0;
    for (int k = 0; k < kFrames; ++k) {
        driver->Advance(k * dt, dt, &values);
        REQUIRE(values.size() == live[k].size());
        for (size_t p = 0; p < values.size(); ++p) {
            INFO("frame " << k << " " << values[p].first);
            REQUIRE(values[p].first == live[k][p].first);
            if (k < firstSlip) {
                CHECK(values[p].second == Approx(live[k][p].second).margin(1e-6));
                ++compared;
            } else if (k == kFrames - 1) {
                CHECK(values[p].second == Approx(live[k][p].second).margin(1e-4));
            }
        }
    }
    INFO(slips << " events slipped a frame; compared " << compared << " values exactly");
    CHECK(slips <= 3);
    // The knobs really moved: the last values are the mapping of the last CC on each knob.
    const ParamState fin = ShowParamState(show);
    int moved = 0;
    for (size_t p = 0; p < 4; ++p) moved += std::abs(live[kFrames - 1][p].second - fin.value[p]) > 1e-3;
    CHECK(moved >= 3);
}
