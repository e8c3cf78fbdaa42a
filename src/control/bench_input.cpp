// RunInputBench: `sdfvj bench input`. Two measurements over real transports:
//   1. latency: send -> input-thread callback (OSC via liblo on loopback; MIDI through JACK when
//      a server runs), and callback -> the start of the frame that applies it (60 fps loop);
//   2. flood: 10,000 OSC messages per second for `seconds` while the 60 fps loop drains, maps
//      and smooths; reports lost events and the per-frame input work with and without the flood.
#include <lo/lo.h>
#include <rtmidi/RtMidi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

#include "control/control.h"

namespace sdfvj {
namespace {

using Clock = std::chrono::steady_clock;

double Median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}
double Percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(p * double(v.size())))];
}

struct FrameLoop {
    explicit FrameLoop(EventQueue& q) : queue(q) {}
    EventQueue& queue;
    Mapping mapping;
    MappingState ms;
    ParamState params;
    std::vector<double> workUs;         // drain + map + smooth, per frame
    std::vector<double> toFrameMs;      // event callback -> frame start
    std::vector<double> sendToCbMs;     // OSC: send time carried in the message -> callback
    std::vector<int> seqSeen;
    double (*now)() = nullptr;

    // Runs frames at `fps` until `until` (clock seconds).
    void Run(double until, double fps) {
        const double dt = 1.0 / fps;
        double next = now();
        MappingActions acts;
        while (next < until) {
            next += dt;
            std::this_thread::sleep_for(std::chrono::duration<double>(std::max(0.0, next - now())));
            double frameStart = now();
            auto t0 = Clock::now();
            std::vector<ControlEvent> events = queue.DrainUntil(frameStart);
            for (const ControlEvent& e : events) {
                ApplyEvent(mapping, ms, e, params, &acts);
                toFrameMs.push_back((frameStart - e.time) * 1e3);
                if (e.source == EventSource::Osc && e.args.size() >= 3 && e.args[1].type == 'i') {
                    seqSeen.push_back(e.args[1].i);
                    sendToCbMs.push_back((e.time - e.args[2].i * 1e-6) * 1e3);
                }
            }
            acts.Clear();
            StepSmoothing(params, dt);
            workUs.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        }
    }
};

Clock::time_point gT0 = Clock::now();
double Now() { return std::chrono::duration<double>(Clock::now() - gT0).count(); }

// Sends /bench/seq f value, i seq, i send-time-us at `rate` per second for `seconds`.
int SendOsc(int port, double rate, double seconds) {
    lo_address a = lo_address_new("127.0.0.1", std::to_string(port).c_str());
    double start = Now();
    int sent = 0;
    while (true) {
        double t = Now() - start;
        if (t >= seconds) break;
        int due = int(t * rate) + 1;
        for (; sent < due; ++sent)
            lo_send(a, "/bench/seq", "fii", float(sent % 1000) / 1000.0f, sent, int(Now() * 1e6));
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    lo_address_free(a);
    return sent;
}

}  // namespace

int RunInputBench(double seconds) {
    gT0 = Clock::now();
    std::vector<ParamDecl> decls = {{"twist", ParamType::Float, 0.0f, -3.0f, 3.0f, "Twist"},
                                    {"scale", ParamType::Float, 1.0f, 0.5f, 2.0f, "Scale"}};
    EventQueue queue;
    InputOptions opt;
    opt.oscPort = 0;
    opt.log = false;
    opt.virtualPortName = "sdfvj-bench";
    opt.midiPort = "sdfvj-bench-sender";
    InputSession session(opt, queue, &Now);
    for (const std::string& s : session.StatusLines()) std::printf("%s\n", s.c_str());
    if (session.OscPort() <= 0) {
        std::fprintf(stderr, "bench input: no OSC port\n");
        return 1;
    }
    FrameLoop loop(queue);
    loop.now = &Now;
    loop.params = MakeParamState(decls);
    ParseMapping("[[map]]\nosc = \"/bench/seq\"\ntarget = \"twist\"\n[[map]]\ncc = 1\ntarget = \"scale\"\n",
                 "bench", &loop.mapping);

    // 1. Baseline frames with no input.
    loop.Run(Now() + 1.0, 60.0);
    std::vector<double> idleWork = loop.workUs;
    loop.workUs.clear();

    // 2. Latency, OSC: 200 messages/s for 2 s.
    std::thread tx([&] { SendOsc(session.OscPort(), 200.0, 2.0); });
    loop.Run(Now() + 2.3, 60.0);
    tx.join();
    loop.Run(Now() + 0.1, 60.0);
    std::printf("OSC latency (%zu msgs): send->callback median %.3f ms p99 %.3f ms; callback->frame start "
                "median %.2f ms p99 %.2f ms (60 fps: ~8.3 ms expected)\n",
                loop.sendToCbMs.size(), Median(loop.sendToCbMs), Percentile(loop.sendToCbMs, 0.99),
                Median(loop.toFrameMs), Percentile(loop.toFrameMs, 0.99));

    // 3. Latency, MIDI through JACK (when a server runs).
    try {
        if (session.StatusLines()[0].rfind("MIDI (JACK)", 0) == 0) {
            RtMidiOut out(RtMidi::UNIX_JACK, "sdfvj-bench-tx");
            out.openVirtualPort("sdfvj-bench-sender");
            session.Poll();
            std::this_thread::sleep_for(std::chrono::milliseconds(300));
            queue.DrainUntil(Now());
            std::vector<double> sendTimes;
            std::vector<double> lat;
            for (int i = 0; i < 200; ++i) {
                std::vector<unsigned char> msg = {0xB0, 1, uint8_t(i % 128)};
                double t = Now();
                out.sendMessage(&msg);
                while (Now() < t + 0.05 && queue.Size() == 0) std::this_thread::sleep_for(std::chrono::microseconds(50));
                for (const ControlEvent& e : queue.DrainUntil(Now() + 1)) lat.push_back((e.time - t) * 1e3);
                std::this_thread::sleep_for(std::chrono::milliseconds(3));
            }
            std::printf("MIDI latency via JACK dummy (%zu msgs, -p 256 @ 48 kHz = 5.3 ms period): send->callback "
                        "median %.3f ms p99 %.3f ms\n", lat.size(), Median(lat), Percentile(lat, 0.99));
        } else {
            std::printf("MIDI latency: skipped (no JACK server)\n");
        }
    } catch (const std::exception& e) {
        std::printf("MIDI latency: skipped (%s)\n", e.what());
    }

    // 4. Flood: 10,000 msg/s for `seconds`.
    loop.seqSeen.clear();
    loop.workUs.clear();
    loop.toFrameMs.clear();
    size_t droppedBefore = queue.Dropped();
    uint64_t malformedBefore = session.Counters().oscMalformed;
    int sent = 0;
    std::thread flood([&] { sent = SendOsc(session.OscPort(), 10000.0, seconds); });
    loop.Run(Now() + seconds + 0.5, 60.0);
    flood.join();
    loop.Run(Now() + 0.2, 60.0);
    std::vector<int> seen = loop.seqSeen;
    std::sort(seen.begin(), seen.end());
    size_t unique = size_t(std::unique(seen.begin(), seen.end()) - seen.begin());
    bool ordered = std::is_sorted(loop.seqSeen.begin(), loop.seqSeen.end());
    std::printf("flood: %d sent in %.0f s (%.0f msg/s), %zu applied, %lld lost, %zu dropped by the queue, "
                "%llu malformed, arrival order %s\n",
                sent, seconds, sent / seconds, unique, (long long)sent - (long long)unique,
                queue.Dropped() - droppedBefore,
                (unsigned long long)(session.Counters().oscMalformed - malformedBefore), ordered ? "kept" : "NOT kept");
    std::printf("per-frame input work (drain+map+smooth): idle median %.1f us max %.1f us; flood median %.1f us "
                "p99 %.1f us max %.1f us (%.0f events/frame)\n",
                Median(idleWork), Percentile(idleWork, 1.0), Median(loop.workUs), Percentile(loop.workUs, 0.99),
                Percentile(loop.workUs, 1.0), loop.workUs.empty() ? 0.0 : double(unique) / loop.workUs.size());
    std::printf("flood callback->frame start: median %.2f ms p99 %.2f ms\n", Median(loop.toFrameMs),
                Percentile(loop.toFrameMs, 0.99));
    return sent - int(unique) == 0 ? 0 : 1;
}

}  // namespace sdfvj
