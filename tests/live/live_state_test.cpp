// The stages of a live frame (src/app/live_session.h) on their own: no window, no GL, no device.
// Each defect of issue 10 that lives in these stages has its regression test here.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "app/live_session.h"

using namespace sdfvj;
namespace fs = std::filesystem;

namespace {

ControlEvent Osc(const std::string& address, OscArg arg) {
    ControlEvent e;
    e.source = EventSource::Osc;
    e.address = address;
    e.args.push_back(arg);
    return e;
}
OscArg Str(const std::string& s) { OscArg a; a.type = 's'; a.s = s; return a; }
OscArg Int(int32_t i) { OscArg a; a.type = 'i'; a.i = i; return a; }
OscArg Float(float f) { OscArg a; a.type = 'f'; a.f = f; return a; }

LiveState Open(ShowOptions so) {
    so.path = "fragment";
    LiveState s;
    std::string err;
    INFO(err);
    REQUIRE(OpenLiveState(so, "", &s, &err));
    s.report.print = false;
    return s;
}

LiveState OpenMidi(const std::string& preset = "") {
    ShowOptions so;
    if (preset.empty()) so.scene = "midi";
    so.preset = preset;
    return Open(so);
}

ParamDecl Decl(const std::string& name, float lo, float hi, float def) {
    ParamDecl d;
    d.name = d.label = name;
    d.minValue = lo;
    d.maxValue = hi;
    d.defaultValue = def;
    return d;
}

bool Said(const LiveState& s, const std::string& text) {
    for (const std::string& line : s.report.recent)
        if (line.find(text) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST_CASE("live_state preset request: numbers too large for an integer are no preset, not a crash", "[live_state]") {
    const std::vector<std::string> presets = {"a.json", "b.json", "c.json"};
    CHECK(ResolvePresetRequest("99999999999999999999999", "a.json", presets).empty());
    CHECK(ResolvePresetRequest("18446744073709551616", "a.json", presets).empty());   // 2^64
    CHECK(ResolvePresetRequest("3", "a.json", presets).empty());
    CHECK(ResolvePresetRequest("1", "a.json", presets) == "b.json");
    CHECK(ResolvePresetRequest("next", "c.json", presets) == "a.json");
    CHECK(ResolvePresetRequest("prev", "a.json", presets) == "c.json");
    CHECK(ResolvePresetRequest("b", "a.json", presets) == "b.json");
    CHECK(ResolvePresetRequest("-1", "a.json", presets).empty());
    CHECK(ResolvePresetRequest("", "a.json", presets).empty());
    CHECK(ResolvePresetRequest("1", "", {}).empty());
}

TEST_CASE("live_state preset request: /sdfvj/preset with a huge number over OSC is reported, the show goes on", "[live_state]") {
    LiveState s = OpenMidi();
    const VariantKey before = s.wanted;
    ApplyControl(s, {Osc("/sdfvj/preset", Str("99999999999999999999999"))}, 1.0);
    REQUIRE_NOTHROW(ApplyActions(s, 1.0));
    CHECK(Said(s, "no such preset"));
    CHECK(s.wanted == before);
    // A valid request by index still works afterwards.
    ApplyControl(s, {Osc("/sdfvj/preset", Str("twisted"))}, 2.0);
    ApplyActions(s, 2.0);
    CHECK(s.currentPreset == "twisted.json");
    CHECK(s.wanted.effects.shadows == 3);
}

TEST_CASE("live_state rebase: an added input keeps every knob, a renamed one starts at its default", "[live_state]") {
    ParamState old = MakeParamState({Decl("twist", -2, 2, 0), Decl("scale", 0.5f, 2, 1)});
    SetParamTarget(old, 0, 1.5f);
    old.value[0] = 1.2f;
    SetParamTarget(old, 1, 1.8f);

    ParamState added = RebaseParams(old, {Decl("twist", -2, 2, 0), Decl("glow", 0, 1, 0.25f), Decl("scale", 0.5f, 2, 1)});
    CHECK(added.target[0] == 1.5f);
    CHECK(added.value[0] == 1.2f);
    CHECK(added.target[1] == 0.25f);   // new: its default
    CHECK(added.target[2] == 1.8f);    // moved to another index: still its value

    ParamState renamed = RebaseParams(old, {Decl("spin", -2, 2, 0.5f), Decl("scale", 0.5f, 1, 1)});
    CHECK(renamed.target[0] == 0.5f);
    CHECK(renamed.target[1] == 1.0f);   // clamped to the new, narrower range
}

TEST_CASE("live_state follow: a scene header that gains an input rebuilds the parameters once, by name", "[live_state]") {
    LiveState s = OpenMidi();
    const int twist = FindParam(s.params, "twist");
    REQUIRE(twist >= 0);
    SetParamTarget(s.params, twist, 1.25f);
    SceneInfo onScreen = s.show.scene;
    onScreen.params.push_back(Decl("glow", 0, 1, 0.5f));
    // Frame after frame with the new header: the knob set by the performer stays (the old code
    // compared counts with the stale header and reset every knob each frame).
    for (int frame = 0; frame < 5; ++frame) {
        FollowScene(s, onScreen);
        StepSmoothing(s.params, 1.0 / 60);
        if (frame == 1) SetParamTarget(s.params, FindParam(s.params, "glow"), 0.9f);
    }
    CHECK(s.params.decls.size() == onScreen.params.size());
    CHECK(s.params.target[(size_t)FindParam(s.params, "twist")] == 1.25f);
    CHECK(s.params.target[(size_t)FindParam(s.params, "glow")] == 0.9f);
    // OSC reaches the new input by name.
    ApplyControl(s, {Osc("/sdfvj/raw/glow", Float(0.3f))}, 1.0);
    CHECK(s.params.target[(size_t)FindParam(s.params, "glow")] == Approx(0.3f));
}

TEST_CASE("live_state effects: /sdfvj/effect/ao i 0 asks for the variant without AO, ssaa for the supersampled one, unknown effects are reported", "[live_state]") {
    LiveState s = OpenMidi();
    REQUIRE(s.wanted.effects.ao);
    ApplyControl(s, {Osc("/sdfvj/effect/ao", Int(0))}, 1.0);
    ApplyActions(s, 1.0);
    CHECK_FALSE(s.wanted.effects.ao);
    ApplyControl(s, {Osc("/sdfvj/effect/nonsense", Int(1))}, 2.0);
    REQUIRE_NOTHROW(ApplyActions(s, 2.0));
    CHECK_FALSE(s.wanted.effects.ao);
    // Anti-aliasing for the audience's big screen: its own variant, off again the same way.
    ApplyControl(s, {Osc("/sdfvj/effect/ssaa", Int(1))}, 3.0);
    ApplyActions(s, 3.0);
    CHECK(s.wanted.effects.supersample == 1);
    CHECK_FALSE(s.wanted.effects.ao);
    ApplyControl(s, {Osc("/sdfvj/effect/ssaa", Int(0))}, 4.0);
    ApplyActions(s, 4.0);
    CHECK(s.wanted.effects.supersample == 0);
}

TEST_CASE("live_state presets: a preset for another scene waits for its program, then cuts to its values", "[live_state]") {
    LiveState s = OpenMidi();
    const SceneInfo midi = s.show.scene;
    REQUIRE(ApplyPresetFile(s, (fs::path(DataRoot()) / "presets" / "bulb.json").string(), false, 1.0));
    CHECK(s.wanted.scenePath.find("mandelbulb") != std::string::npos);
    FollowScene(s, midi);                      // still compiling: the midi scene stays on screen
    CHECK(FindParam(s.params, "twist") >= 0);
    CHECK(FindParam(s.params, "power") < 0);
    CHECK(!s.pendingTargets.empty());
    SceneInfo bulb;
    std::string err;
    REQUIRE(FindScene("mandelbulb", &bulb, &err));
    FollowScene(s, bulb);                      // compiled: its parameters, at the preset's values
    const int power = FindParam(s.params, "power");
    REQUIRE(power >= 0);
    CHECK(s.params.value[(size_t)power] == 8.0f);
    CHECK(s.pendingTargets.empty());
}

TEST_CASE("live_state presets: while the scene on stage or its post chain is saved broken mid-edit, a preset for it still applies on their last good headers", "[live_state]") {
    const fs::path dir = fs::temp_directory_path() / ("sdfvj-live-stage-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path root(DataRoot());
    const fs::path scene = dir / "stage.glsl", post = dir / "glow.fs", other = dir / "other.glsl";
    fs::copy_file(root / "shaders" / "scenes" / "midi.glsl", scene, fs::copy_options::overwrite_existing);
    fs::copy_file(root / "shaders" / "scenes" / "midi.glsl", other, fs::copy_options::overwrite_existing);
    fs::copy_file(root / "shaders" / "isf" / "bloom.fs", post, fs::copy_options::overwrite_existing);
    auto read = [](const fs::path& p) { std::ifstream f(p); return std::string(std::istreambuf_iterator<char>(f), {}); };
    auto breakFile = [&](const fs::path& p, const std::string& from, const std::string& to) {
        std::string text = read(p);
        REQUIRE(text.find(from) != std::string::npos);
        std::ofstream(p, std::ios::trunc) << text.replace(text.find(from), from.size(), to);
    };
    ShowOptions so;
    so.scene = scene.string();
    so.post = post.string();
    LiveState s = Open(so);
    const fs::path preset = dir / "p.json";
    std::ofstream(preset) << "{\"scene\": \"" << scene.string() << "\", \"params\": {\"twist\": 0.25, \"threshold\": 0.5}}\n";

    breakFile(scene, "/*{", "/*{{");                  // the header's JSON broken
    breakFile(post, "\"PASSES\": [", "\"PASSES\": {\"a\": 1}, \"X\": [");   // PASSES of the wrong type
    REQUIRE(ApplyPresetFile(s, preset.string(), false, 1.0));
    CHECK(Said(s, "stage.glsl:1"));
    CHECK(Said(s, "the scene on stage keeps its last good header"));
    CHECK(Said(s, "glow.fs:12"));
    CHECK(Said(s, "the post chain on stage keeps its last good inputs"));
    CHECK(s.currentPreset == "p.json");
    CHECK(s.wanted.scenePath == s.show.scene.path);   // no new program asked for
    SceneInfo onScreen = s.show.scene;   // as live follows a scene with a post chain (SceneWithPost)
    onScreen.params = ShowDecls(s.show);
    FollowScene(s, onScreen);
    CHECK(s.params.target[(size_t)FindParam(s.params, "twist")] == 0.25f);
    REQUIRE(FindParam(s.params, "threshold") >= 0);  // the post chain's input, from its last good header
    CHECK(s.params.target[(size_t)FindParam(s.params, "threshold")] == 0.5f);

    // Another scene file that does not parse is still refused: only the stage's own files stand in.
    std::ofstream(other, std::ios::trunc) << "/*{ \"INPUTS\": [ }*/\n";
    std::ofstream(preset, std::ios::trunc) << "{\"scene\": \"" << other.string() << "\"}\n";
    CHECK_FALSE(ApplyPresetFile(s, preset.string(), false, 2.0));
    CHECK(Said(s, "keeping the current preset"));
    fs::remove_all(dir);
}

TEST_CASE("live_state files: a broken mapping save says file:line and keeps the last good mapping", "[live_state]") {
    const fs::path dir = fs::temp_directory_path() / ("sdfvj-live-state-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path mapping = dir / "m.toml";
    std::ofstream(mapping) << "[[map]]\ncc = 1\ntarget = \"twist\"\n";
    ShowOptions so;
    so.scene = "midi";
    LiveState s;
    std::string err;
    REQUIRE(OpenLiveState(so, mapping.string(), &s, &err));
    s.report.print = false;
    REQUIRE(s.mapping.entries.size() == 1);
    std::ofstream(mapping) << "[[map]]\ncc = 1\ntarget = \"twist\"\n[[map]]\ncc = \"seven\"\n";
    REQUIRE_NOTHROW(ApplyFileChanges(s, {mapping.string()}, 1.0));
    CHECK(Said(s, "m.toml:5"));
    CHECK(Said(s, "keeping the previous mapping"));
    CHECK(s.mapping.entries.size() == 1);
    fs::remove_all(dir);
}

TEST_CASE("live_state report: a flood of bad input prints at most one line a second", "[live_state]") {
    LiveReport r;
    r.print = false;
    for (int i = 0; i < 1000; ++i) r.Limited(10.0 + i * 0.001, {"bad " + std::to_string(i)});
    CHECK(r.recent.size() == 1);
    r.Limited(11.5, {"late"});
    REQUIRE(r.recent.size() == 2);
    CHECK(r.recent.back().find("and 999 more") != std::string::npos);
}

TEST_CASE("live_state report: bytes from outside are printed as text, and each kind of line is limited on its own", "[live_state]") {
    CHECK(PrintableLine(std::string("pre\x01set\x1b[31m\xff", 13)) == "pre?set?[31m?");
    CHECK(PrintableLine("caf\xc3\xa9\nline") == "caf\xc3\xa9\nline");
    CHECK(PrintableLine(std::string(5000, 'x')).size() == 2003);
    LiveReport r;
    r.print = false;
    r.Limited(1.0, {"bad osc"});
    r.Limited(1.1, {"preset a"}, "preset");
    r.Limited(1.2, {"preset b"}, "preset");
    CHECK(r.recent.size() == 2);
}

TEST_CASE("live_state scripted preset: a broken expression keeps the previous preset, a good one runs on the show clock", "[live_state]") {
    const fs::path dir = fs::temp_directory_path() / ("sdfvj-live-script-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    LiveState s = OpenMidi();
    const fs::path bad = dir / "bad.json";
    std::ofstream(bad) << "{\n  \"scene\": \"midi\",\n  \"params\": {\n    \"twist\": \"0.4 + * beat\"\n  }\n}\n";
    CHECK_FALSE(ApplyPresetFile(s, bad.string(), false, 1.0));
    CHECK(Said(s, "bad.json:4: expression for 'twist' does not parse"));
    CHECK(s.currentPreset.empty());
    const fs::path good = dir / "good.json";
    std::ofstream(good) << "{\n  \"scene\": \"midi\",\n  \"bpm\": 60,\n  \"params\": {\n    \"twist\": \"lfo_saw(beat / 4)\"\n  }\n}\n";
    REQUIRE(ApplyPresetFile(s, good.string(), false, 10.0));
    FollowScene(s, s.show.scene);
    RunAutomation(s, 12.0, 0);   // beat 22 of the show (120 bpm until 10 s, then 60): lfo_saw(5.5)
    CHECK(s.params.value[(size_t)FindParam(s.params, "twist")] == Approx(0.0f).margin(1e-5));
    RunAutomation(s, 13.0, 1);
    CHECK(s.params.value[(size_t)FindParam(s.params, "twist")] == Approx(0.5f));
    fs::remove_all(dir);
}
