// The running `sdfvj live` the reload tests drive (live_reload_test.cpp, live_render_process_test.cpp):
// a real window under Xvfb (ctest fixture `xvfb`), OSC from the `oscsend` tool, the frame values
// from the --log-params log, files saved the way editors save.
#pragma once
#include <catch2/catch.hpp>

#include <dirent.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "live_util.h"

namespace sdfvj::test {

// Writes `text` next to `path` and renames it over `path`, as editors save.
inline void SaveLikeAnEditor(const std::string& path, const std::string& text) {
    const std::filesystem::path p(path);
    const std::filesystem::path tmp = p.parent_path() / ("." + p.filename().string() + ".new");
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << text;
        REQUIRE(out.good());
    }
    std::filesystem::rename(tmp, p);
}

inline std::string JoinLines(const std::vector<std::string>& lines) {
    std::string s;
    for (const std::string& l : lines) s += l + "\n";
    return s;
}

// A running `sdfvj live` (scene midi unless a preset says otherwise) that logs every frame's
// values; stopped when the test ends, however it ends.
struct LiveShow {
    std::string dir, log, params;
    pid_t pid = -1;
    int oscPort = 0;

    // `root`: a data root (SDFVJ_ROOT) with its own shaders/, presets/ and mappings/ to edit.
    LiveShow(const std::string& folder, const std::vector<std::string>& extra, const std::string& root = "",
             const std::vector<EnvChange>& moreEnv = {})
        : dir(folder) {
        log = dir + "/live.log";
        params = dir + "/params.txt";
        oscPort = FreeUdpPort();
        // --seconds only bounds a run the test failed to stop; the test stops it long before.
        std::vector<std::string> argv = {SDFVJ_BIN, "live", "--size", "160x90", "--seconds", "100", "--path", "fragment",
                                         "--effects", "none", "--osc-port", std::to_string(oscPort), "--midi",
                                         "no-such-controller", "--log-params", params, "--hide-overlay"};
        argv.insert(argv.end(), extra.begin(), extra.end());
        std::vector<EnvChange> env = {{"DISPLAY", Display()}, {"JACK_NO_START_SERVER", "1"}};
        if (!root.empty()) env.push_back({"SDFVJ_ROOT", root});
        env.insert(env.end(), moreEnv.begin(), moreEnv.end());
        pid = Spawn(argv, log, env);
    }
    ~LiveShow() { Stop(); }

    // True while the process has not exited (one that has is reaped, and Stop has nothing to do).
    bool Running() {
        if (pid <= 0) return false;
        if (waitpid(pid, nullptr, WNOHANG) == 0) return true;
        pid = -1;
        return false;
    }
    void Stop() {
        if (pid <= 0) return;
        kill(pid, SIGTERM);
        WaitExit(pid, 10);   // SIGKILLs it after 10 s
        pid = -1;
    }
    std::string Log() const { return ReadText(log); }
    bool WaitForLog(const std::string& text, size_t times, double seconds) const {
        return PollFor(seconds, [&] { return CountInFile(log, text) >= times; });
    }
    void Osc(const std::string& address, float value) const {
        int rc = Run({"oscsend", "localhost", std::to_string(oscPort), address, "f", std::to_string(value)},
                     dir + "/oscsend.log", 10);
        INFO(ReadText(dir + "/oscsend.log"));
        REQUIRE(rc == 0);
    }
    std::vector<Frame> Frames() const { return ReadParamLog(params); }
    // Waits (up to `seconds`) for a frame whose values match `want` (to 1e-4); true when one came.
    // *at is the index of that frame in the log.
    bool WaitForValues(const std::map<std::string, float>& want, double seconds, size_t* at = nullptr) const {
        return PollFor(seconds, [&] {
            const std::vector<Frame> frames = Frames();
            for (size_t i = frames.size(); i-- > 0;) {
                if (!Matches(frames[i], want)) continue;
                if (at) *at = i;
                return true;
            }
            return false;
        });
    }
    static bool Matches(const Frame& f, const std::map<std::string, float>& want) {
        for (const auto& [name, v] : want) {
            auto it = f.second.find(name);
            if (it == f.second.end() || std::fabs(it->second - v) > 1e-4f) return false;
        }
        return true;
    }
    std::string LastFrame() const {
        const std::vector<Frame> frames = Frames();
        if (frames.empty()) return "(no frame logged)";
        std::string s = std::to_string(frames.back().first);
        for (const auto& [name, v] : frames.back().second) s += " " + name + "=" + std::to_string(v);
        return s;
    }
    // Each change of the set of logged names, with the frame index and that frame's values: shows
    // when a header reached the parameters (and whether an older one came back).
    std::string NameHistory() const {
        const std::vector<Frame> frames = Frames();
        std::string s, names, prev;
        for (size_t i = 0; i < frames.size(); ++i) {
            names.clear();
            for (const auto& [name, v] : frames[i].second) names += name + " ";
            if (names == prev) continue;
            prev = names;
            s += "  frame " + std::to_string(i) + ":";
            for (const auto& [name, v] : frames[i].second) s += " " + name + "=" + std::to_string(v);
            s += "\n";
        }
        // Whether the loop still runs (a hung show logs nothing more) and the process lives.
        std::this_thread::sleep_for(std::chrono::seconds(1));
        const size_t later = Frames().size();
        return s + "  (" + std::to_string(frames.size()) + " frames logged, " + std::to_string(later - frames.size()) +
               " more in the next second; process " + (pid > 0 && kill(pid, 0) == 0 ? "alive" : "gone") + ")\n";
    }
    // At least `more` frames are logged after frame index `from` (the loop went on).
    bool WaitForFramesAfter(size_t from, size_t more, double seconds) const {
        return PollFor(seconds, [&] { return Frames().size() >= from + 1 + more; });
    }
};

inline const double kDeadline = 10.0;   // generous: software GL on a loaded machine

// REQUIRE for a wait on the running show: on failure it shows the show's log and last frame as
// they are then (INFO would capture them before the wait).
#define REQUIRE_LIVE(show, cond)                                                                   \
    do {                                                                                           \
        const bool ok_ = (cond);                                                                   \
        if (!ok_) {                                                                                \
            INFO("live log:\n" << (show).Log() << "parameter sets:\n" << (show).NameHistory()        \
                                << "last frame: " << (show).LastFrame());                          \
            INFO(#cond);                                                                           \
            REQUIRE(ok_);                                                                          \
        }                                                                                          \
    } while (0)
// A preset that crossfades to primitives over `seconds` (root/presets/to_primitives.json).
inline void WriteCrossfadePreset(const std::string& root, const std::string& seconds) {
    std::ofstream(root + "/presets/to_primitives.json")
        << R"({"scene": "primitives", "params": {"spin": 0.8}, "morph": {"seconds": )" << seconds
        << R"(, "easing": "linear", "scenes": "crossfade"}})";
}

// A copy of the repository's data (shaders, presets, mappings) that a test may edit.
inline std::string CopyDataRoot(const std::string& dir) {
    const std::filesystem::path root = std::filesystem::path(dir) / "root";
    std::filesystem::create_directories(root);
    for (const char* sub : {"shaders", "presets", "mappings"})
        std::filesystem::copy(std::filesystem::path(SDFVJ_SOURCE_ROOT) / sub, root / sub, std::filesystem::copy_options::recursive);
    return root.string();
}

inline std::string ReadAll(const std::string& path) { return ReadText(path); }

// The midi scene with its header's INPUTS line for `twist` replaced by `replacement`.
inline std::string MidiWithTwistLine(const std::string& midi, const std::string& replacement) {
    const std::string twist =
        "    {\"NAME\": \"twist\", \"TYPE\": \"float\", \"DEFAULT\": 0.5, \"MIN\": -3.0, \"MAX\": 3.0, \"LABEL\": \"Twist\"},";
    const size_t at = midi.find(twist);
    REQUIRE(at != std::string::npos);
    return midi.substr(0, at) + replacement + midi.substr(at + twist.size());
}

// The midi scene with an input added after `twist`: glow, 0..1, default 0.25.
inline std::string MidiWithGlow(const std::string& midi) {
    return MidiWithTwistLine(midi,
        "    {\"NAME\": \"twist\", \"TYPE\": \"float\", \"DEFAULT\": 0.5, \"MIN\": -3.0, \"MAX\": 3.0, \"LABEL\": \"Twist\"},\n"
        "    {\"NAME\": \"glow\", \"TYPE\": \"float\", \"DEFAULT\": 0.25, \"MIN\": 0.0, \"MAX\": 1.0, \"LABEL\": \"Glow\"},");
}

// The longest gap between two frames logged in [from, to], seconds.
inline double LongestGap(const std::vector<Frame>& frames, size_t from, size_t to) {
    double gap = 0;
    for (size_t i = from + 1; i <= to && i < frames.size(); ++i) gap = std::max(gap, frames[i].first - frames[i - 1].first);
    return gap;
}

// The processes `sdfvj live` started (its children: render servers, with --render-process).
inline std::vector<pid_t> Children(pid_t parent) {
    std::vector<pid_t> out;
    const std::string task = "/proc/" + std::to_string(parent) + "/task";
    if (DIR* d = opendir(task.c_str())) {
        while (dirent* e = readdir(d)) {
            if (e->d_name[0] == '.') continue;
            std::istringstream words(ReadText(task + "/" + e->d_name + "/children"));
            for (long pid = 0; words >> pid;) out.push_back((pid_t)pid);
        }
        closedir(d);
    }
    return out;
}

// Hands a `live --scene midi --render-process` show, started on a root with WriteCrossfadePreset,
// that preset by OSC, and returns once the crossfade is said ("over SAID s") and the new values drawn.
inline void StartCrossfade(LiveShow& show, const std::string& dir, const std::string& said) {
    REQUIRE_LIVE(show, show.WaitForLog("the scene is drawn by a render process", 1, 60));
    REQUIRE_LIVE(show, show.WaitForValues({{"twist", 0.5f}}, kDeadline));
    REQUIRE_LIVE(show, PollFor(20, [&] { return Children(show.pid).size() == 2; }));   // on screen, and a spare
    REQUIRE(Run({"oscsend", "localhost", std::to_string(show.oscPort), "/sdfvj/preset", "s", "to_primitives"}, dir + "/oscsend.log", 10) == 0);
    REQUIRE_LIVE(show, show.WaitForLog("scene morph: midi -> primitives, a crossfade of their render processes' frames over " + said + " s", 1, 60));
    REQUIRE_LIVE(show, show.WaitForValues({{"spin", 0.8f}}, kDeadline));
}

}  // namespace sdfvj::test
