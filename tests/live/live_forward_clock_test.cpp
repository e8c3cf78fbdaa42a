// `live --forward`'s show clock (issue 15, follower nodes): the leader's /sdfvj/clock. The pure
// pieces: the leader clock of live_sync.h (a follower's clock locks to it, seeks, holds,
// freewheels) and /sdfvj/clock on the wire. Then real shows on loopback under Xvfb (fixture
// `xvfb`): both --log-params logs, matched by show time, agree frame by frame while twist glides;
// a follower driven by a test leader (liblo) follows its time across a jump, a stop and silence.
#include <catch2/catch.hpp>

#include <lo/lo.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <thread>
#include <map>
#include <string>
#include <vector>

#include "app/live_forward.h"
#include "app/live_sync.h"
#include "live_forward_util.h"
#include "live_util.h"

using namespace sdfvj;
using namespace sdfvj::test;

namespace {

ControlEvent ClockEvent(double local, double seconds, bool running, const std::vector<std::pair<std::string, float>>& values) {
    ControlEvent e;
    e.source = EventSource::Osc;
    e.time = local;
    e.address = "/sdfvj/clock";
    auto i = [](int32_t v) {
        OscArg a;
        a.type = 'i';
        a.i = v;
        a.f = float(v);
        return a;
    };
    e.args = {i(int32_t(std::floor(seconds))), i(int32_t(std::lround((seconds - std::floor(seconds)) * 1e6))), i(running ? 1 : 0)};
    for (const auto& [name, v] : values) {
        OscArg n, f;
        n.type = 's';
        n.s = name;
        f.f = v;
        e.args.push_back(n);
        e.args.push_back(f);
    }
    return e;
}

// One LiveSyncStep at `wall` over `events`; the lines said are appended to *said.
double Step(LiveSync& s, std::vector<ControlEvent> events, double wall, std::vector<std::string>* said) {
    return LiveSyncStep(s, &events, wall, said);
}

bool Said(const std::vector<std::string>& said, const std::string& text) {
    return std::any_of(said.begin(), said.end(), [&](const std::string& l) { return l.find(text) != std::string::npos; });
}

}  // namespace

TEST_CASE("live forward: a follower's show clock locks to the leader's /sdfvj/clock, seeks, holds, freewheels") {
    LiveSync s;
    std::vector<std::string> said;
    ParamDecl twist;
    twist.name = "twist";
    twist.minValue = -3.0f;
    twist.maxValue = 3.0f;
    ParamState p = MakeParamState({twist});
    // No leader: the wall clock, nothing said, values untouched.
    CHECK(Step(s, {}, 0.5, &said) == 0.5);
    CHECK_FALSE(LiveSyncFollows(s));
    CHECK(LiveSyncRunning(s));
    CHECK(LiveSyncStatus(s, 0.5).empty());
    // Heard: locked to its time, advanced by the local clock since the message arrived; its
    // values replace this frame's (clamped to the range here).
    CHECK(Step(s, {ClockEvent(1.0, 50.0, true, {{"twist", 1.5f}, {"other", 9.0f}})}, 1.01, &said) == Approx(50.01));
    CHECK(Said(said, "leader locked at 50.000 s"));
    CHECK(LiveSyncFollows(s));
    FollowLeaderValues(s, p);
    CHECK(p.value[0] == 1.5f);
    Step(s, {ClockEvent(1.02, 50.02, true, {{"twist", 7.0f}})}, 1.03, &said);
    FollowLeaderValues(s, p);
    CHECK(p.value[0] == 3.0f);
    // Jitter: a message that arrived late would put the clock back 20 ms; it is held instead.
    CHECK(Step(s, {}, 1.10, &said) == Approx(50.10));
    CHECK(Step(s, {ClockEvent(1.11, 50.09, true, {})}, 1.11, &said) == Approx(50.10));
    CHECK(Step(s, {}, 1.20, &said) == Approx(50.18));
    // A jump seeks, said once.
    said.clear();
    CHECK(Step(s, {ClockEvent(1.3, 80.0, true, {})}, 1.3, &said) == Approx(80.0));
    CHECK(Said(said, "leader jump to 80.000 s (from 50.280 s): seek"));
    CHECK(s.leader.seeks == 1);
    // Stopped: the clock holds there; the same stop again says nothing more.
    said.clear();
    CHECK(Step(s, {ClockEvent(1.4, 90.0, false, {{"twist", -1.0f}})}, 1.4, &said) == Approx(90.0));
    CHECK(Step(s, {ClockEvent(1.5, 90.0, false, {{"twist", -1.0f}})}, 1.9, &said) == Approx(90.0));
    CHECK(said.size() == 1);
    CHECK(Said(said, "leader locate to 90.000 s"));
    CHECK_FALSE(LiveSyncRunning(s));
    FollowLeaderValues(s, p);
    CHECK(p.value[0] == -1.0f);
    // Running again, then silence: after 0.5 s it freewheels at speed 1 (said once), and the
    // node's own values stand; it never stops by itself.
    said.clear();
    CHECK(Step(s, {ClockEvent(2.0, 90.0, true, {{"twist", -2.0f}})}, 2.0, &said) == Approx(90.0));
    CHECK(Step(s, {}, 2.4, &said) == Approx(90.4));
    CHECK(said.empty());
    CHECK(Step(s, {}, 2.6, &said) == Approx(90.6));
    CHECK(Said(said, "leader lost (no /sdfvj/clock for 0.50 s): freewheeling"));
    CHECK(LiveSyncRunning(s));
    p.value[0] = 0.25f;
    FollowLeaderValues(s, p);
    CHECK(p.value[0] == 0.25f);
    CHECK(Step(s, {}, 100.0, &said) == Approx(188.0));
    CHECK(LiveSyncStatus(s, 100.0).find("leader 188.000 s master lost: freewheeling") != std::string::npos);
    // Back: locked again, said once.
    said.clear();
    CHECK(Step(s, {ClockEvent(100.0, 188.0, true, {})}, 100.0, &said) == Approx(188.0));
    CHECK(Said(said, "leader back at 188.000 s: locked"));
    // A bad copy (from a take) is a line, not a clock.
    said.clear();
    ControlEvent bad = ClockEvent(100.1, 1.0, true, {});
    bad.args[1].i = -3;
    CHECK(Step(s, {bad}, 100.1, &said) == Approx(188.1));
    CHECK(Said(said, "/sdfvj/clock: microseconds -3 out of range, expected 0..999999"));
    // Under --sync mtc the clock stays MTC's (waiting: 0); the leader's values still apply.
    LiveSync mtc;
    mtc.mode = LiveSync::Mode::Mtc;
    CHECK(Step(mtc, {ClockEvent(1.0, 50.0, true, {{"twist", 0.5f}})}, 1.0, &said) == 0.0);
    FollowLeaderValues(mtc, p);
    CHECK(p.value[0] == 0.5f);
    CHECK(LiveSyncStatus(mtc, 1.0).find("(values only)") != std::string::npos);
}

TEST_CASE("live forward: the leader's frames read late together after a stall here are no jump, a step back is") {
    LiveSync s;
    std::vector<std::string> said;
    // Locked at 50 s, a frame every 10 ms.
    CHECK(Step(s, {ClockEvent(1.0, 50.0, true, {})}, 1.0, &said) == Approx(50.0));
    CHECK(Step(s, {ClockEvent(1.01, 50.01, true, {})}, 1.01, &said) == Approx(50.01));
    said.clear();
    // A 155 ms stall here: the leader's next 15 frames (50.02 .. 50.16) are read at once at 1.165.
    std::vector<ControlEvent> batch;
    for (int k = 0; k < 15; ++k) batch.push_back(ClockEvent(1.165, 50.02 + 0.01 * k, true, {}));
    CHECK(Step(s, batch, 1.165, &said) == Approx(50.16));
    INFO((said.empty() ? "" : said[0]));
    CHECK_FALSE(Said(said, "jump"));
    CHECK(s.leader.seeks == 0);
    CHECK(s.lateFrames == 7);   // 50.02 .. 50.08, 85 ms or more behind the clock (a seek: 2 frames, 80 ms)
    CHECK(LiveSyncStatus(s, 1.165).find("; 7 leader frames read late") != std::string::npos);   // the overlay says so
    // On time again: it locks on as before.
    CHECK(Step(s, {ClockEvent(1.17, 50.17, true, {})}, 1.17, &said) == Approx(50.17));
    CHECK(Step(s, {ClockEvent(1.18, 50.18, true, {})}, 1.18, &said) == Approx(50.18));
    CHECK(s.leader.seeks == 0);
    // A leader that steps back (its time before the last one taken) seeks, however late it was read.
    CHECK(Step(s, {ClockEvent(1.5, 50.0, true, {})}, 1.5, &said) == Approx(50.0));
    CHECK(Said(said, "leader jump to 50.000 s"));
    CHECK(s.leader.seeks == 1);
    // A leader that stays behind longer than it may go unheard (0.5 s) is no late read: it seeks.
    CHECK(Step(s, {ClockEvent(1.6, 50.01, true, {})}, 1.6, &said) == Approx(50.1));
    CHECK(Step(s, {ClockEvent(1.8, 50.02, true, {})}, 1.8, &said) == Approx(50.3));
    CHECK(s.leader.seeks == 1);
    CHECK(Step(s, {ClockEvent(2.05, 50.03, true, {})}, 2.05, &said) == Approx(50.03));
    CHECK(s.leader.seeks == 2);
}

TEST_CASE("live forward: the leader's frame goes out as /sdfvj/clock that the decoder takes back") {
    lo_server server = lo_server_new(nullptr, nullptr);   // a free port
    REQUIRE(server);
    struct Got {
        std::vector<ControlEvent> events;
        std::vector<std::string> why;
    } got;
    lo_server_add_method(
        server, nullptr, nullptr,
        [](const char* path, const char* types, lo_arg** argv, int argc, lo_message, void* data) {
            Got& g = *static_cast<Got*>(data);
            ControlEvent e;
            std::string why;
            if (DecodeOscMessage(path, types, reinterpret_cast<const void* const*>(argv), argc, 0.0, &e, &why))
                g.events.push_back(std::move(e));
            else
                g.why.push_back(why);
            return 0;
        },
        &got);
    LiveForward f;
    std::string error;
    INFO("port " << lo_server_get_port(server) << ": " << error);
    REQUIRE(OpenLiveForward("127.0.0.1:" + std::to_string(lo_server_get_port(server)), &f, &error));
    LiveState state;
    ParamDecl a, b;
    a.name = "twist";
    a.minValue = -3.0f;
    a.maxValue = 3.0f;
    b.name = "scale";
    b.maxValue = 2.0f;
    state.params = MakeParamState({a, b});
    state.params.value = {-1.234567f, 0.75f};
    ForwardFrame(f, state, 3601.0000125, false, 0.25f, 128.0f);
    ForwardFrame(f, state, 12.9999999, true, 0.5f, 90.0f);   // rounds up to the next whole second
    for (int k = 0; k < 50 && got.events.size() + got.why.size() < 2; ++k) lo_server_recv_noblock(server, 100);
    lo_server_free(server);
    INFO(got.why.size() << " refused" << (got.why.empty() ? "" : ": " + got.why[0]));
    REQUIRE(got.events.size() == 2);
    LeaderClock c;
    REQUIRE(ParseLeaderClock(got.events[0].args, &c, &error));
    CHECK(c.seconds == Approx(3601.000013).margin(1e-9));
    CHECK_FALSE(c.running);
    CHECK(c.values == std::vector<std::pair<std::string, float>>{{"twist", -1.234567f}, {"scale", 0.75f}, {"@beat", 0.25f}, {"@bpm", 128.0f}});
    REQUIRE(ParseLeaderClock(got.events[1].args, &c, &error));
    CHECK(c.seconds == 13.0);
    CHECK(c.running);
    CHECK(f.frames == 2);
    // A follower draws the leader's tempo while it hears it: u_beat and u_bpm of the frame.
    LiveSync sync;
    std::vector<std::string> said;
    float beat = 0.9f, bpm = 120.0f;
    CHECK_FALSE(LeaderTempo(sync, &beat, &bpm));
    CHECK(beat == 0.9f);
    std::vector<ControlEvent> events = {got.events[1]};
    events[0].time = 1.0;
    LiveSyncStep(sync, &events, 1.0, &said);
    CHECK(events.empty());   // the clock frame is the show clock's only
    CHECK(IsLeaderClock(got.events[1]));
    CHECK_FALSE(IsLeaderClock(ControlEvent{}));
    REQUIRE(LeaderTempo(sync, &beat, &bpm));
    CHECK(beat == 0.5f);
    CHECK(bpm == 90.0f);
    // The tempo pairs are no parameter: FollowLeaderValues leaves a scene's inputs to their names.
    ParamState p = state.params;
    FollowLeaderValues(sync, p);
    CHECK(p.value == std::vector<float>{-1.234567f, 0.75f});
}

TEST_CASE("live forward: both --log-params agree frame by frame, matched by show time, while twist glides") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "forward-frames");
    const int followerPort = FreeUdpPort();
    FreshDir(dir, "leader"), FreshDir(dir, "follower");
    Node follower(dir + "/follower", followerPort, {});
    Node leader(dir + "/leader", FreeUdpPort(), {"--forward", "127.0.0.1:" + std::to_string(followerPort)});
    const bool locked = PollFor(kDeadline, [&] {
        return leader.Frames().size() > 2 && CountInFile(follower.log, "leader locked at") == 1 && follower.Frames().size() > 2;
    });
    INFO("leader " << leader.Describe() << "\nfollower " << follower.Describe());
    REQUIRE(locked);
    const double from = leader.Frames().back().first;
    // twist glides (smoothing 0.05 s) between -2.4 and 2.4, a new target every 0.3 s.
    for (int k = 0; k < 8; ++k) {
        leader.Osc({"/sdfvj/param/twist", "f", k % 2 ? "0.9" : "0.1"});
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
    const std::vector<Frame> l = leader.Frames(), f = follower.Frames();
    REQUIRE(l.size() > 10);
    // Each follower frame shows the values of one leader frame: the one the leader rendered last
    // at or before the follower's show time (j), or one a little before it (the follower drew
    // before the /sdfvj/clock of frames j, j-1... arrived: each leaves the leader after its input
    // stages, and crosses loopback). Matched: every value equal (both print %g). Allowed: a frame
    // the leader had replaced at most kWithin before the follower's show time (its staleness; 0
    // for j itself, however long the leader's frame took); reported: how many frames back.
    // A frame shown later than that still has to be one of the leader's; on a loaded machine
    // (CI's sanitizer pass on 2 cores: 8 of 933 frames 20-40 ms late once) a few may be.
    const double kWithin = 0.020;
    size_t compared = 0, moving = 0, unmatched = 0, late = 0;
    std::map<size_t, size_t> back;   // leader frames back from j -> follower frames
    std::vector<double> lag;         // staleness: follower show time - when the leader replaced the frame shown
    float worst = 0;                 // |follower twist - leader twist at j|: what showing an earlier frame costs
    auto equal = [](const Frame& a, const Frame& b) {
        for (const auto& [name, v] : b.second) {
            auto it = a.second.find(name);
            if (it == a.second.end() || std::fabs(it->second - v) > 1e-4f * std::max(1.0f, std::fabs(v))) return false;
        }
        return !b.second.empty();
    };
    for (const Frame& ff : f) {
        if (ff.first < from + kWithin || ff.first > l.back().first) continue;
        // The log's time column has 0.1 ms: a leader frame within 0.1 ms after counts as at.
        size_t j = std::upper_bound(l.begin(), l.end(), ff.first + 1e-4, [](double t, const Frame& x) { return t < x.first; }) - l.begin();
        REQUIRE(j > 1);
        --j;
        ++compared;
        moving += std::fabs(l[j].second.at("twist") - l[j - 1].second.at("twist")) > 1e-3f;
        worst = std::max(worst, std::fabs(ff.second.at("twist") - l[j].second.at("twist")));
        // Searched back through every earlier leader frame: one shown later than kLate is a late
        // frame (counted below), not a wrong one; a wrong one matches no leader frame at all.
        size_t k = j + 1;
        while (k-- > 0)
            if (equal(ff, l[k])) break;
        INFO("follower frame at " << ff.first << " twist " << ff.second.at("twist") << "; leader frame " << j << " at "
                                  << l[j].first << " twist " << l[j].second.at("twist"));
        if (k > j) {   // no leader frame had these values
            ++unmatched;
            CHECK(false);
            continue;
        }
        ++back[j - k];
        lag.push_back(k == j ? 0.0 : ff.first - l[k + 1].first);
        late += lag.back() > kWithin;
    }
    std::sort(lag.begin(), lag.end());
    std::vector<double> leaderGaps;
    for (size_t i = 1; i < l.size(); ++i) leaderGaps.push_back(l[i].first - l[i - 1].first);
    std::sort(leaderGaps.begin(), leaderGaps.end());
    REQUIRE(!lag.empty());
    std::string hist;
    for (const auto& [n, count] : back) hist += " " + std::to_string(n) + " back: " + std::to_string(count) + ",";
    std::printf("live forward: %zu follower frames compared (%zu while twist moved), %zu unmatched, %zu shown more than "
                "20 ms late; leader frame shown:%s "
                "replaced by the leader before the follower's show time by: median %.1f ms, max %.1f ms (leader frame "
                "median %.1f ms); |twist - leader twist at "
                "the same show time| max %.3f\n",
                compared, moving, unmatched, late, hist.c_str(), 1000 * lag[lag.size() / 2], 1000 * lag.back(),
                1000 * leaderGaps[leaderGaps.size() / 2], worst);
    CHECK(compared >= 40);
    CHECK(moving >= 10);                       // the comparison saw twist gliding, not just resting values
    CHECK(unmatched == 0);
    // At most 2 % of frames later than kWithin (5 % under a sanitizer: CI's sanitizer pass on 2
    // cores once showed 21 of 1056 frames late, 5 of them 100-200 ms, the follower starved).
    CHECK(late <= compared / (kSanitized ? 20 : 50));
    CHECK(back[0] + back[1] >= compared / 2);  // mostly the leader frame at its show time or the one before
}

TEST_CASE("live forward: a follower follows a leader's clock across a jump, a stop and silence") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "forward-clock");
    const int port = FreeUdpPort();
    Node follower(dir, port, {});
    REQUIRE(PollFor(kDeadline, [&] { return follower.Frames().size() > 2; }));
    lo_address to = lo_address_new("127.0.0.1", std::to_string(port).c_str());
    REQUIRE(to);
    // The leader's timeline (t: seconds since it started), a /sdfvj/clock every 10 ms:
    //   [0, 1.5)    runs from 100 s
    //   [1.5, 3)    jumps to 500 s and runs
    //   [3, 4.5)    stopped at 520 s
    //   [4.5, 6)    runs from 520 s
    //   [6, 7.5)    silent: the follower freewheels on at speed 1
    auto leader = [](double t) {
        if (t < 1.5) return 100.0 + t;
        if (t < 3.0) return 500.0 + (t - 1.5);
        if (t < 4.5) return 520.0;
        return 520.0 + (t - 4.5);
    };
    using Clock = std::chrono::steady_clock;
    const Clock::time_point t0 = Clock::now();
    LogWatcher watcher(follower.params, t0);
    for (int k = 0;; ++k) {
        const double t = k * 0.01;
        if (t >= 6.0 - 1e-9) break;
        std::this_thread::sleep_until(t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t)));
        const double show = leader(t);
        const int32_t seconds = int32_t(std::floor(show)), micros = int32_t(std::lround((show - seconds) * 1e6)) % 1000000;
        lo_send(to, "/sdfvj/clock", "iiisf", seconds, micros, (t >= 3.0 && t < 4.5) ? 0 : 1, "spin", 0.3f + 0.1f * float(t));
    }
    std::this_thread::sleep_until(t0 + std::chrono::milliseconds(7500));
    const std::vector<SeenLine> seen = watcher.Stop();
    lo_address_free(to);
    INFO(ReadText(follower.log));
    // Compared where the leader was settled (0.3 s after each change). A line is seen up to one
    // render frame after its frame began; the error allowed is one 25 fps frame (40 ms) plus that gap.
    auto settled = [](double t) {
        for (double change : {0.0, 1.5, 3.0, 4.5, 6.0})
            if (t >= change && t < change + 0.3) return false;
        return t < 7.4;
    };
    std::vector<double> errors;
    int checked[5] = {0, 0, 0, 0, 0};
    for (size_t i = 1; i < seen.size(); ++i) {
        const SeenLine& x = seen[i];
        if (!settled(x.at)) continue;
        const double gap = SinceLastRead(seen, i);
        const int phase = x.at < 1.5 ? 0 : x.at < 3 ? 1 : x.at < 4.5 ? 2 : x.at < 6 ? 3 : 4;
        ++checked[phase];
        INFO("seen at " << x.at << " s: show " << x.show << ", leader " << leader(x.at) << ", frame gap " << gap);
        if (phase == 2) {
            CHECK(x.show == Approx(520.0).margin(1e-3));   // holding: not a tick further
        } else {
            CHECK(std::fabs(x.show - leader(x.at)) <= 0.04 + gap + 0.005);
            errors.push_back(std::fabs(x.show - leader(x.at)));
        }
    }
    for (int p = 0; p < 5; ++p) {
        INFO("phase " << p);
        CHECK(checked[p] >= 5);
    }
    std::sort(errors.begin(), errors.end());
    REQUIRE(!errors.empty());
    CHECK(errors[errors.size() / 2] < 0.04);
    std::printf("live forward: clock: %zu frames compared (per phase %d %d %d %d %d), |show - leader| median %.1f ms, max %.1f ms\n",
                errors.size(), checked[0], checked[1], checked[2], checked[3], checked[4], 1000 * errors[errors.size() / 2],
                1000 * errors.back());
    CHECK(CountInFile(follower.log, "leader locked at 10") == 1);
    CHECK(CountInFile(follower.log, "leader jump to 50") == 1);
    CHECK(CountInFile(follower.log, "leader locate to 520.000 s") == 1);
    CHECK(CountInFile(follower.log, "leader lost (no /sdfvj/clock for 0.50 s): freewheeling") == 1);
}

