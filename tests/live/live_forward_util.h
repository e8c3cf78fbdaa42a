// What the `live --forward` tests share (live_forward_test.cpp, live_forward_clock_test.cpp): one
// `sdfvj live` on loopback logging every frame's values, polled for what it logged.
#pragma once
#include <signal.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "live_util.h"

namespace sdfvj::test {

// Built with a sanitizer (CI's second pass): everything runs several times slower.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(undefined_behavior_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

inline constexpr double kDeadline = 30.0;   // generous: software GL, two shows, two loaded cores

// One `sdfvj live` (scene midi) logging every frame's values; stopped when the test ends.
struct Node {
    std::string dir, log, params;
    int oscPort = 0;
    pid_t pid = -1;
    Node(const std::string& folder, int port, const std::vector<std::string>& extra) : dir(folder), oscPort(port) {
        log = dir + "/live.log";
        params = dir + "/params.txt";
        std::vector<std::string> argv = {SDFVJ_BIN, "live", "--scene", "midi", "--size", "96x54", "--seconds", "100",
                                         "--path", "fragment", "--effects", "none", "--osc-port", std::to_string(port),
                                         "--midi", "no-such-controller", "--log-params", params, "--hide-overlay"};
        argv.insert(argv.end(), extra.begin(), extra.end());
        pid = Spawn(argv, log, {{"DISPLAY", Display()}, {"JACK_NO_START_SERVER", "1"}});
    }
    ~Node() {
        if (pid <= 0) return;
        kill(pid, SIGTERM);
        WaitExit(pid, 10);
    }
    void Osc(const std::vector<std::string>& message) const {
        std::vector<std::string> argv = {"oscsend", "localhost", std::to_string(oscPort)};
        argv.insert(argv.end(), message.begin(), message.end());
        INFO(ReadText(dir + "/oscsend.log"));
        REQUIRE(Run(argv, dir + "/oscsend.log", 10) == 0);
    }
    std::vector<Frame> Frames() const { return ReadParamLog(params); }
    static bool Matches(const Frame& f, const std::map<std::string, float>& want) {
        for (const auto& [name, v] : want) {
            auto it = f.second.find(name);
            if (it == f.second.end() || std::fabs(it->second - v) > 1e-4f) return false;
        }
        return true;
    }
    // Index of the first logged frame that matches `want`, waiting up to `seconds`; -1 if none.
    long WaitFor(const std::map<std::string, float>& want, double seconds) const {
        long at = -1;
        PollFor(seconds, [&] {
            const std::vector<Frame> frames = Frames();
            for (size_t i = 0; i < frames.size(); ++i)
                if (Matches(frames[i], want)) return at = (long)i, true;
            return false;
        });
        return at;
    }
    std::string Describe() const {
        const std::vector<Frame> frames = Frames();
        std::string s = "log:\n" + ReadText(log) + "frames: " + std::to_string(frames.size());
        if (!frames.empty())
            for (const auto& [name, v] : frames.back().second) s += " " + name + "=" + std::to_string(v);
        return s;
    }
};

}  // namespace sdfvj::test
