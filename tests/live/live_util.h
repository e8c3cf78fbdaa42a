// Helpers shared by the `live` tests: the Xvfb display of the ctest fixture, the --log-params
// log ("time name=value ..." per frame) and polling a growing log file with a deadline.
#pragma once
#include <catch2/catch.hpp>

#include <chrono>
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

// How often `text` occurs in the file at `path` now.
inline size_t CountInFile(const std::string& path, const std::string& text) {
    const std::string s = ReadText(path);
    size_t n = 0;
    for (size_t at = s.find(text); at != std::string::npos; at = s.find(text, at + text.size())) ++n;
    return n;
}

}  // namespace sdfvj::test
