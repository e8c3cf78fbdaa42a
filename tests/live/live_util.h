// Helpers shared by the `live` tests: the Xvfb display of the ctest fixture, the --log-params
// log ("time name=value ..." per frame) and polling a growing log file with a deadline.
#pragma once
#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "proc_util.h"

namespace sdfvj::test {

// ":N" of the Xvfb the live_xvfb_start fixture started.
inline std::string Display() {
    std::string n = ReadText(std::string(SDFVJ_XVFB_STATE) + ".display");
    while (!n.empty() && (n.back() == '\n' || n.back() == ' ')) n.pop_back();
    INFO("no Xvfb display number in " << SDFVJ_XVFB_STATE << ".display (is the live_xvfb_start fixture running?)");
    REQUIRE(!n.empty());
    return ":" + n;
}

// One line of the --log-params log: the live clock and the values that frame rendered.
using Frame = std::pair<double, std::map<std::string, float>>;

// The frames logged so far. A last line without its newline (being written) is left out.
inline std::vector<Frame> ReadParamLog(const std::string& path) {
    std::vector<Frame> frames;
    std::string text = ReadText(path);
    const size_t end = text.rfind('\n');
    text.resize(end == std::string::npos ? 0 : end + 1);
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        Frame f;
        ls >> f.first;
        std::string kv;
        while (ls >> kv) {
            size_t eq = kv.find('=');
            if (eq != std::string::npos) f.second[kv.substr(0, eq)] = std::stof(kv.substr(eq + 1));
        }
        frames.push_back(f);
    }
    return frames;
}

// Polls `until` every 20 ms for at most `seconds`; true as soon as it holds.
inline bool PollFor(double seconds, const std::function<bool()>& until) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    for (;;) {
        if (until()) return true;
        if (std::chrono::steady_clock::now() > end) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

// Watches a --log-params log from its end: each line appended after it started, with when the
// test saw it (seconds since `t0`) and the show time it holds. A master's time at `at` is then
// at most one render frame later than the frame's own (the line is written as the frame draws).
struct SeenLine {
    double at = 0.0, show = 0.0;
};
// How long before seen[i].at its line may have been written: since the watcher last saw an
// earlier line. Lines read in one batch share their `at` (the watcher fell behind: ASan on a
// loaded machine), so the line just before is no bound; the batch before it is.
inline double SinceLastRead(const std::vector<SeenLine>& seen, size_t i) {
    size_t j = i;
    while (j > 0 && seen[j - 1].at >= seen[i].at) --j;
    return j > 0 ? seen[i].at - seen[j - 1].at : 0.0;
}
class LogWatcher {
public:
    LogWatcher(const std::string& path, std::chrono::steady_clock::time_point t0)
        : thread_([this, path, t0] {
              std::ifstream in(path, std::ios::binary);
              in.seekg(0, std::ios::end);
              std::string partial;
              while (!done_) {
                  std::string chunk(1 << 16, '\0');
                  in.clear();
                  in.read(chunk.data(), (std::streamsize)chunk.size());
                  chunk.resize((size_t)in.gcount());
                  const double at = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                  partial += chunk;
                  for (size_t nl; (nl = partial.find('\n')) != std::string::npos; partial.erase(0, nl + 1))
                      seen_.push_back({at, std::atof(partial.c_str())});
                  if (chunk.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
              }
          }) {}
    ~LogWatcher() { Stop(); }
    // The lines seen; the watcher stops.
    std::vector<SeenLine> Stop() {
        done_ = true;
        if (thread_.joinable()) thread_.join();
        return seen_;
    }

private:
    std::atomic<bool> done_{false};
    std::vector<SeenLine> seen_;
    std::thread thread_;   // last: starts once the members it uses exist
};

// How often `text` occurs in the file at `path` now.
inline size_t CountInFile(const std::string& path, const std::string& text) {
    const std::string s = ReadText(path);
    size_t n = 0;
    for (size_t at = s.find(text); at != std::string::npos; at = s.find(text, at + text.size())) ++n;
    return n;
}

}  // namespace sdfvj::test
