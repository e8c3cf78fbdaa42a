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

#include "live_show.h"

using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

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
    SaveLikeAnEditor(scene, MidiWithGlow(good));
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
