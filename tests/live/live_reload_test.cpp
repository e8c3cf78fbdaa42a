// `sdfvj live` reloads the mapping file and the preset on stage when they are saved, and keeps
// the last good one when a save is broken (issue 5). A real window under Xvfb (ctest fixture
// `xvfb`), OSC from the `oscsend` tool, the frame values from the --log-params log. The files are
// copies in a test folder, saved the way editors save (write a temporary file, rename it over).
#include <catch2/catch.hpp>

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "live_util.h"

using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

// Writes `text` next to `path` and renames it over `path`, as editors save.
void SaveLikeAnEditor(const std::string& path, const std::string& text) {
    const fs::path p(path);
    const fs::path tmp = p.parent_path() / ("." + p.filename().string() + ".new");
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << text;
        REQUIRE(out.good());
    }
    fs::rename(tmp, p);
}

std::string JoinLines(const std::vector<std::string>& lines) {
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

const double kDeadline = 10.0;   // generous: software GL on a loaded machine

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

// Each mapping version sends OSC address /test/knob (0..1) somewhere else. Line 9 is the
// entry's target in every version; the broken one has a syntax error there.
std::vector<std::string> MappingLines(const std::string& targetLine, const std::string& rangeLine) {
    return {"# live_reload test mapping",         // 1
            "[profile]",                          // 2
            "name = \"reload test\"",             // 3
            "channel = \"any\"",                  // 4
            "",                                   // 5
            "[[map]]",                            // 6
            "osc = \"/test/knob\"",               // 7
            "smoothing = 0",                      // 8
            targetLine,                           // 9
            rangeLine};                           // 10
}

}  // namespace

TEST_CASE("live_reload mapping: a saved mapping file remaps OSC at once, a broken save keeps the last good one") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "reload-mapping");
    const std::string mapping = dir + "/knobs.toml";
    {
        std::ofstream(mapping) << JoinLines(MappingLines("target = \"twist\"", "range = [-3.0, 3.0]"));
    }
    LiveShow show(dir, {"--scene", "midi", "--mapping", mapping});
    REQUIRE_LIVE(show, show.WaitForLog("OSC: listening on UDP port " + std::to_string(show.oscPort), 1, 20));

    // The scene's defaults to start with (scale 1, twist 0.5, displacement 0.04).
    REQUIRE_LIVE(show, show.WaitForValues({{"scale", 1.0f}, {"twist", 0.5f}, {"displacement", 0.04f}}, 20));

    // Version 1: /test/knob -> twist over [-3, 3].
    show.Osc("/test/knob", 1.0f);
    REQUIRE_LIVE(show, show.WaitForValues({{"twist", 3.0f}, {"displacement", 0.04f}, {"scale", 1.0f}}, kDeadline));

    // Version 2, saved while running: the same knob drives displacement over [0.05, 0.25].
    SaveLikeAnEditor(mapping, JoinLines(MappingLines("target = \"displacement\"", "range = [0.05, 0.25]")));
    REQUIRE_LIVE(show, show.WaitForLog("reloaded " + mapping, 1, kDeadline));
    show.Osc("/test/knob", 0.5f);
    REQUIRE_LIVE(show, show.WaitForValues({{"displacement", 0.15f}, {"twist", 3.0f}, {"scale", 1.0f}}, kDeadline));

    // A broken save (line 9: `target = = ...`): reported as file:line:, version 2 stays.
    SaveLikeAnEditor(mapping, JoinLines(MappingLines("target = = \"scale\"", "range = [0.5, 1.5]")));
    REQUIRE_LIVE(show, show.WaitForLog("keeping the previous mapping", 1, kDeadline));
    {
        const std::string out = show.Log();
        INFO(out);
        CHECK(out.find(mapping + ":9:") != std::string::npos);
        CHECK(CountInFile(show.log, "reloaded " + mapping) == 1);
    }
    show.Osc("/test/knob", 1.0f);
    REQUIRE_LIVE(show, show.WaitForValues({{"displacement", 0.25f}, {"twist", 3.0f}, {"scale", 1.0f}}, kDeadline));

    // Fixed: the knob now drives scale over [0.5, 1.5]; displacement stays where it was.
    SaveLikeAnEditor(mapping, JoinLines(MappingLines("target = \"scale\"", "range = [0.5, 1.5]")));
    REQUIRE_LIVE(show, show.WaitForLog("reloaded " + mapping, 2, kDeadline));
    show.Osc("/test/knob", 0.25f);
    REQUIRE_LIVE(show, show.WaitForValues({{"scale", 0.75f}, {"displacement", 0.25f}, {"twist", 3.0f}}, kDeadline));
    CHECK(show.Running());
}

namespace {

// The preset on stage; line 5 holds twist in every version (the broken one has `,,` there).
std::string PresetText(const std::string& twistLine, float displacement) {
    return JoinLines({"{",                                                                    // 1
                      "  \"scene\": \"midi\",",                                               // 2
                      "  \"params\": {",                                                      // 3
                      "    \"scale\": 1.25,",                                                 // 4
                      twistLine,                                                              // 5
                      "    \"displacement\": " + std::to_string(displacement) + ",",          // 6
                      "    \"smoothness\": 0.3",                                              // 7
                      "  }",                                                                  // 8
                      "}"});                                                                  // 9
}

}  // namespace

TEST_CASE("live_reload preset: the preset on stage applies again when saved, a broken save keeps the values") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "reload-preset");
    const std::string preset = dir + "/stage.json";
    {
        std::ofstream(preset) << PresetText("    \"twist\": 1.5,", 0.1f);
    }
    LiveShow show(dir, {"--preset", preset});
    REQUIRE_LIVE(show, show.WaitForLog("OSC: listening on UDP port " + std::to_string(show.oscPort), 1, 20));

    // The first frame already renders the preset's values (not the scene defaults).
    REQUIRE_LIVE(show, PollFor(20, [&] { return !show.Frames().empty(); }));
    {
        const Frame first = show.Frames().front();
        CHECK(first.second.at("scale") == Approx(1.25f));
        CHECK(first.second.at("twist") == Approx(1.5f));
        CHECK(first.second.at("displacement") == Approx(0.1f));
        CHECK(first.second.at("smoothness") == Approx(0.3f));
        CHECK(first.second.at("spin") == Approx(0.3f));   // not in the preset: the scene default
    }

    // Saved with another twist: the running show glides there.
    SaveLikeAnEditor(preset, PresetText("    \"twist\": 2.5,", 0.1f));
    REQUIRE_LIVE(show, show.WaitForValues({{"twist", 2.5f}, {"scale", 1.25f}, {"displacement", 0.1f}}, kDeadline));
    CHECK(show.WaitForLog("reloaded " + preset + " (midi)", 1, kDeadline));

    // A broken save (line 5: `,,`), which would also move twist and displacement: reported as
    // file:line:, and no frame from the save on shows any of its values.
    const size_t beforeBroken = show.Frames().size();
    SaveLikeAnEditor(preset, PresetText("    \"twist\": -1.0,,", 0.2f));
    REQUIRE_LIVE(show, show.WaitForLog("keeping the current values", 1, kDeadline));
    {
        const std::string out = show.Log();
        INFO(out);
        CHECK(out.find(preset + ":5:") != std::string::npos);
        CHECK(CountInFile(show.log, "reloaded " + preset) == 1);
    }
    const size_t atError = show.Frames().size();
    REQUIRE_LIVE(show, show.WaitForFramesAfter(atError, 10, kDeadline));   // the show goes on
    {
        const std::vector<Frame> frames = show.Frames();
        for (size_t i = beforeBroken; i < frames.size(); ++i) {
            INFO("frame " << i << " at " << frames[i].first << " s");
            CHECK(frames[i].second.at("twist") == Approx(2.5f).margin(1e-4));
            CHECK(frames[i].second.at("displacement") == Approx(0.1f).margin(1e-4));
        }
    }

    // Fixed: the new values apply.
    SaveLikeAnEditor(preset, PresetText("    \"twist\": -1.0,", 0.2f));
    REQUIRE_LIVE(show, show.WaitForValues({{"twist", -1.0f}, {"displacement", 0.2f}, {"scale", 1.25f}}, kDeadline));
    CHECK(show.WaitForLog("reloaded " + preset + " (midi)", 2, kDeadline));
    CHECK(show.Running());
}

namespace {

// A copy of the repository's data (shaders, presets, mappings) that a test may edit.
std::string CopyDataRoot(const std::string& dir) {
    const fs::path root = fs::path(dir) / "root";
    fs::create_directories(root);
    for (const char* sub : {"shaders", "presets", "mappings"})
        fs::copy(fs::path(SDFVJ_SOURCE_ROOT) / sub, root / sub, fs::copy_options::recursive);
    return root.string();
}

std::string ReadAll(const std::string& path) { return ReadText(path); }

// The midi scene with its header's INPUTS line for `twist` replaced by `replacement`.
std::string MidiWithTwistLine(const std::string& midi, const std::string& replacement) {
    const std::string twist =
        "    {\"NAME\": \"twist\", \"TYPE\": \"float\", \"DEFAULT\": 0.5, \"MIN\": -3.0, \"MAX\": 3.0, \"LABEL\": \"Twist\"},";
    const size_t at = midi.find(twist);
    REQUIRE(at != std::string::npos);
    return midi.substr(0, at) + replacement + midi.substr(at + twist.size());
}

}  // namespace

TEST_CASE("live_reload first shader: a scene that does not compile keeps the window open, the fix starts the show") {
    // Issue 10, defect 5: live exited when the first program failed to compile.
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "reload-first");
    const std::string root = CopyDataRoot(dir);
    const std::string scene = root + "/shaders/scenes/midi.glsl";
    const std::string good = ReadAll(scene);
    const size_t mapAt = good.find("vec4 map(vec3 p)");
    REQUIRE(mapAt != std::string::npos);
    const size_t brokenLine = 1 + (size_t)std::count(good.begin(), good.begin() + (long)mapAt, '\n');
    SaveLikeAnEditor(scene, good.substr(0, mapAt) + "vec4 map(vec3 p) { return fBx(p); }\nvec4 mapUnused(vec3 p)" +
                                good.substr(mapAt + std::string("vec4 map(vec3 p)").size()));
    LiveShow show(dir, {"--scene", "midi"}, root);
    REQUIRE_LIVE(show, show.WaitForLog("midi.glsl:" + std::to_string(brokenLine) + ":", 1, 30));
    std::this_thread::sleep_for(std::chrono::seconds(1));
    REQUIRE_LIVE(show, show.Running());
    SaveLikeAnEditor(scene, good);
    REQUIRE_LIVE(show, show.WaitForLog("shader reloaded", 1, 30));
    const size_t at = show.Frames().size();
    REQUIRE_LIVE(show, show.WaitForFramesAfter(at, 5, kDeadline));
    CHECK(show.Running());
}

TEST_CASE("live_reload retune: a save that changes only numbers is on screen without a compile, then the optimized program") {
    // Issue 12: the literal tier in the show (src/render/live_program.h SetLiteralTier).
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "reload-retune");
    const std::string root = CopyDataRoot(dir);
    const std::string scene = root + "/shaders/scenes/midi.glsl";
    const std::string good = ReadAll(scene);
    LiveShow show(dir, {"--scene", "midi"}, root, {{"SDFVJ_LITERAL_TIER", "1"}});   // off by default on llvmpipe
    REQUIRE_LIVE(show, show.WaitForLog("changes only numbers in its functions shows at once (literal tier)", 1, 60));
    const std::string from = "vec4(0.95f, 0.30f, 0.12f,", to = "vec4(0.10f, 0.30f, 0.95f,";
    const size_t at = good.find(from);
    REQUIRE(at != std::string::npos);
    SaveLikeAnEditor(scene, good.substr(0, at) + to + good.substr(at + from.size()));
    REQUIRE_LIVE(show, show.WaitForLog("shader retuned: the new numbers are on screen", 1, 30));
    // The optimized program of the same save follows ("shader reloaded" is said only after an
    // error, so the frames going on and no error line are what is checked).
    const size_t frames = show.Frames().size();
    REQUIRE_LIVE(show, show.WaitForFramesAfter(frames, 10, kDeadline));
    CHECK(show.Running());
    CHECK(show.Log().find("error") == std::string::npos);
    // A structural save (a new statement) is not a retune: no second "retuned" line.
    const size_t mapAt = good.find("vec4 map(vec3 p) {");
    REQUIRE(mapAt != std::string::npos);
    SaveLikeAnEditor(scene, good.substr(0, mapAt) + "vec4 map(vec3 p) {\n    p.x += 0.0f * p.y;" +
                                good.substr(mapAt + std::string("vec4 map(vec3 p) {").size()));
    std::this_thread::sleep_for(std::chrono::seconds(2));
    CHECK(CountInFile(show.log, "shader retuned") == 1);
    CHECK(show.Running());
}

TEST_CASE("live_reload prefetch: once the show is quiet the pads' and presets' variants compile ahead, and the show goes on") {
    // Issue 12's "compile the variants a preset list or effect pad can reach in the background"
    // (off by default on llvmpipe, forced here; LiveProgram::Prefetch is tested in test_render).
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "reload-prefetch");
    LiveShow show(dir, {"--scene", "midi"}, "", {{"SDFVJ_PREFETCH", "1"}});
    REQUIRE_LIVE(show, show.WaitForLog("variants an effect pad or a preset reaches compile in the background", 1, 60));
    std::this_thread::sleep_for(std::chrono::seconds(2));
    show.Osc("/sdfvj/effect/ao", 1.0f);
    REQUIRE_LIVE(show, show.WaitForLog("sdfvj live: effects", 1, kDeadline));
    const size_t at = show.Frames().size();
    REQUIRE_LIVE(show, show.WaitForFramesAfter(at, 10, kDeadline));
    CHECK(show.Running());
}

TEST_CASE("live_reload scene header: an added input keeps every knob, a wrong-typed field is reported and the show goes on") {
    // Issue 10, defects 2 and 4: a LABEL that is a number killed live (nlohmann type_error), and a
    // header that gained an input reset every knob each frame (parameters rebuilt by count).
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "reload-header");
    const std::string root = CopyDataRoot(dir);
    const std::string scene = root + "/shaders/scenes/midi.glsl";
    const std::string good = ReadAll(scene);
    LiveShow show(dir, {"--scene", "midi"}, root);
    REQUIRE_LIVE(show, show.WaitForLog("OSC: listening on UDP port " + std::to_string(show.oscPort), 1, 20));
    show.Osc("/sdfvj/raw/twist", 2.0f);
    REQUIRE_LIVE(show, show.WaitForValues({{"twist", 2.0f}}, kDeadline));

    // A number where LABEL wants a string: one line with file:line, the show goes on.
    SaveLikeAnEditor(scene, MidiWithTwistLine(good,
        "    {\"NAME\": \"twist\", \"TYPE\": \"float\", \"DEFAULT\": 0.5, \"MIN\": -3.0, \"MAX\": 3.0, \"LABEL\": 5},"));
    REQUIRE_LIVE(show, show.WaitForLog("midi.glsl:5:", 1, kDeadline));
    size_t at = show.Frames().size();
    REQUIRE_LIVE(show, show.WaitForFramesAfter(at, 5, kDeadline));
    CHECK(show.Frames().back().second.at("twist") == Approx(2.0f));

    // An added input: it appears at its default, the knob set before stays.
    SaveLikeAnEditor(scene, MidiWithTwistLine(good,
        "    {\"NAME\": \"twist\", \"TYPE\": \"float\", \"DEFAULT\": 0.5, \"MIN\": -3.0, \"MAX\": 3.0, \"LABEL\": \"Twist\"},\n"
        "    {\"NAME\": \"glow\", \"TYPE\": \"float\", \"DEFAULT\": 0.25, \"MIN\": 0.0, \"MAX\": 1.0, \"LABEL\": \"Glow\"},"));
    REQUIRE_LIVE(show, show.WaitForValues({{"glow", 0.25f}, {"twist", 2.0f}}, 30));
    show.Osc("/sdfvj/raw/glow", 0.75f);
    REQUIRE_LIVE(show, show.WaitForValues({{"glow", 0.75f}, {"twist", 2.0f}}, kDeadline));
    at = show.Frames().size();
    REQUIRE_LIVE(show, show.WaitForFramesAfter(at, 10, kDeadline));
    {
        const std::vector<Frame> frames = show.Frames();
        for (size_t i = at; i < frames.size(); ++i) {
            INFO("frame " << i);
            CHECK(frames[i].second.at("twist") == Approx(2.0f).margin(1e-3));
            CHECK(frames[i].second.at("glow") == Approx(0.75f).margin(1e-3));
        }
    }
    // Renamed (header and code): the new name answers OSC, the old one is gone.
    std::string renamed = MidiWithTwistLine(good,
        "    {\"NAME\": \"warp\", \"TYPE\": \"float\", \"DEFAULT\": 0.5, \"MIN\": -3.0, \"MAX\": 3.0, \"LABEL\": \"Warp\"},");
    for (size_t p = renamed.find("u_twist"); p != std::string::npos; p = renamed.find("u_twist", p)) renamed.replace(p, 7, "u_warp");
    SaveLikeAnEditor(scene, renamed);
    REQUIRE_LIVE(show, PollFor(30, [&] { const auto f = show.Frames(); return !f.empty() && f.back().second.count("warp"); }));
    show.Osc("/sdfvj/raw/warp", -1.5f);
    if (!show.WaitForValues({{"warp", -1.5f}}, kDeadline)) {
        // Once in a CI run the value never came (the test's output was cut before saying why). Said
        // here with what the frames logged, then sent once more: the renamed input must answer.
        WARN("/sdfvj/raw/warp -1.5 not on a frame after " << kDeadline << " s; parameter sets:\n" << show.NameHistory()
                                                          << "log:\n" << show.Log());
        show.Osc("/sdfvj/raw/warp", -1.5f);
    }
    REQUIRE_LIVE(show, show.WaitForValues({{"warp", -1.5f}}, kDeadline));
    CHECK(show.Frames().back().second.count("twist") == 0);
    CHECK(show.Running());
}

TEST_CASE("live_reload effect toggle and library save at once: the show keeps rendering") {
    // Issue 10, defect 3: toggling an effect and saving a library file while the new variant
    // compiled freed the program on screen (segmentation fault).
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "reload-toggle");
    const std::string root = CopyDataRoot(dir);
    const std::string lib = root + "/shaders/lib/combinators.glsl";
    const std::string text = ReadAll(lib);
    LiveShow show(dir, {"--scene", "midi"}, root);
    REQUIRE_LIVE(show, show.WaitForLog("OSC: listening on UDP port " + std::to_string(show.oscPort), 1, 20));
    for (int round = 0; round < 3; ++round) {
        const int rc = Run({"oscsend", "localhost", std::to_string(show.oscPort), "/sdfvj/effect/ao", "i",
                            std::to_string(round % 2)}, dir + "/oscsend.log", 10);
        REQUIRE(rc == 0);
        SaveLikeAnEditor(lib, text + "\n// saved " + std::to_string(round) + "\n");
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        REQUIRE_LIVE(show, show.Running());
    }
    const size_t at = show.Frames().size();
    REQUIRE_LIVE(show, show.WaitForFramesAfter(at, 5, 30));
    CHECK(show.Running());
}

TEST_CASE("live_reload scene morph: a preset switch to another scene morphs the fields in one program, or crossfades "
          "when the preset says so, and the frames keep coming") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "scene-morph");
    const std::string root = CopyDataRoot(dir);
    {
        std::ofstream(root + "/presets/to_field.json")
            << R"({"scene": "primitives", "params": {"spin": 0.8}, "morph": {"seconds": 1.0, "easing": "linear"}})";
        std::ofstream(root + "/presets/to_frames.json")
            << R"({"scene": "midi", "params": {"twist": 1.0}, "morph": {"seconds": 1.0, "scenes": "crossfade"}})";
    }
    LiveShow show(dir, {"--scene", "midi"}, root);
    REQUIRE_LIVE(show, show.WaitForLog("OSC: listening on UDP port " + std::to_string(show.oscPort), 1, 20));
    REQUIRE_LIVE(show, PollFor(20, [&] { return !show.Frames().empty(); }));
    auto preset = [&](const std::string& name) {
        REQUIRE(Run({"oscsend", "localhost", std::to_string(show.oscPort), "/sdfvj/preset", "s", name},
                    dir + "/oscsend.log", 10) == 0);
    };

    // midi -> primitives: one program marches both fields.
    preset("to_field");
    REQUIRE_LIVE(show, show.WaitForLog("scene morph: midi -> primitives as one field over 1.00 s", 1, 30));
    // The morph ends on the new scene alone (its inputs in the log), and the loop goes on.
    REQUIRE_LIVE(show, show.WaitForValues({{"spin", 0.8f}}, 30));
    size_t at = show.Frames().size();
    REQUIRE_LIVE(show, show.WaitForFramesAfter(at, 10, kDeadline));

    // primitives -> midi with "scenes": "crossfade": no field morph.
    preset("to_frames");
    REQUIRE_LIVE(show, show.WaitForValues({{"twist", 1.0f}}, 30));
    at = show.Frames().size();
    REQUIRE_LIVE(show, show.WaitForFramesAfter(at, 10, kDeadline));
    const std::string log = show.Log();
    INFO(log);
    CHECK(CountInFile(show.log, "as one field") == 1);
    CHECK(log.find("internal error") == std::string::npos);
    CHECK(log.find("crossfading the frames instead") == std::string::npos);
    CHECK(show.Running());
}
