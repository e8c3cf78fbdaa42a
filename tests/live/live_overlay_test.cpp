// The performer's overlay (src/app/live_overlay.h): drawn in a real window under Xvfb, and its
// plain-data parts on their own: preset save round trip, number keys, the event monitor, learn.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "app/live_overlay.h"
#include "app/live_session.h"
#include "gl_fixture.h"
#include "live_util.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

ControlEvent Midi(uint8_t status, uint8_t d1, uint8_t d2, double time = 0.0) {
    ControlEvent e;
    e.time = time;
    e.midi[0] = status;
    e.midi[1] = d1;
    e.midi[2] = d2;
    e.midiSize = 3;
    return e;
}

ControlEvent OscFloat(const std::string& address, float f) {
    ControlEvent e;
    e.source = EventSource::Osc;
    e.address = address;
    OscArg a;
    a.f = f;
    e.args.push_back(a);
    return e;
}

void WriteText(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

std::string Slurp(const fs::path& path) { return ReadText(path.string()); }

// `sdfvj live` for 3 s on the midi scene with its spin stopped, the overlay shown or hidden.
Image ShotOfLive(const std::string& name, bool overlay) {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, name), shot = dir + "/shot.png", log = dir + "/live.log";
    std::vector<std::string> argv = {SDFVJ_BIN, "live", "--scene", "midi", "--size", "640x360", "--seconds", "3",
                                     "--path", "fragment", "--effects", "none", "--param", "spin=0",
                                     "--osc-port", "0", "--midi", "no-such-controller", "--screenshot", shot};
    if (!overlay) argv.push_back("--hide-overlay");
    pid_t pid = Spawn(argv, log, {{"DISPLAY", Display()}, {"JACK_NO_START_SERVER", "1"}});
    const int rc = WaitExit(pid, 60);
    INFO(ReadText(log));
    REQUIRE(rc == 0);
    Image img;
    REQUIRE(LoadPng(shot, &img));
    REQUIRE(img.width == 640);
    return img;
}

// Mean |a-b| over the RGB channels of a rectangle in pixels.
double MeanDiff(const Image& a, const Image& b, int x0, int y0, int x1, int y1) {
    double sum = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int c = 0; c < 3; ++c) {
                const size_t i = ((size_t)y * a.width + x) * 4 + c;
                sum += std::abs(int(a.rgba[i]) - int(b.rgba[i]));
            }
    return sum / ((double)(x1 - x0) * (y1 - y0) * 3);
}

// Pixels of a rectangle whose colour is ImGui's active title bar (dark theme: 41, 74, 122).
int TitleBarPixels(const Image& img, int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const uint8_t* p = &img.rgba[((size_t)y * img.width + x) * 4];
            n += std::abs(p[0] - 41) < 12 && std::abs(p[1] - 74) < 12 && std::abs(p[2] - 122) < 12;
        }
    return n;
}

// Standard deviation of luma over a rectangle in pixels: flat colour gives 0.
double LumaSpread(const Image& img, int x0, int y0, int x1, int y1) {
    double sum = 0, sum2 = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const uint8_t* p = &img.rgba[((size_t)y * img.width + x) * 4];
            const double l = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            sum += l;
            sum2 += l * l;
        }
    const double n = (double)(x1 - x0) * (y1 - y0), mean = sum / n;
    return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}

PresetSnapshot MidiSnapshot() {
    PresetSnapshot s;
    s.scene = "midi";
    s.values = {{"scale", 1.25f}, {"twist", 0.3f}, {"displacement", 0.07f}, {"smoothness", 0.45f}};
    s.effects.shadows = 2;
    s.effects.ao = true;
    return s;
}

}  // namespace

TEST_CASE("live_overlay window: the overlay is drawn over the scene, and --hide-overlay leaves the scene alone") {
    const Image shown = ShotOfLive("overlay-shown", true), hidden = ShotOfLive("overlay-hidden", false);
    // The overlay window sits at (10, 10): its title bar and the first rows are there.
    const double overlayDiff = MeanDiff(shown, hidden, 10, 10, 300, 120);
    INFO("mean difference in the overlay region " << overlayDiff);
    CHECK(overlayDiff > 15.0);
    CHECK(TitleBarPixels(shown, 10, 10, 300, 30) > 500);
    CHECK(TitleBarPixels(hidden, 10, 10, 300, 30) < 50);
    // Not an empty panel: text and sliders make the region far from flat.
    const double spread = LumaSpread(shown, 10, 30, 300, 120), flat = LumaSpread(hidden, 10, 30, 300, 120);
    INFO("luma spread with the overlay " << spread << ", without " << flat);
    CHECK(spread > 20.0);
    // Outside the overlay (the right edge), both runs show the same still scene.
    const double outside = MeanDiff(shown, hidden, 610, 200, 640, 360);
    INFO("mean difference outside the overlay " << outside);
    CHECK(outside < 6.0);
}

TEST_CASE("live_overlay presets: save-as writes presets/NAME.json that LoadPreset reads back with the same values") {
    const fs::path dir = FreshDir(SDFVJ_LIVE_OUT, "overlay-save");
    std::string error;
    const std::string path = SavePresetAs(dir.string(), "mine", MidiSnapshot(), &error);
    INFO(error);
    REQUIRE(path == (dir / "mine.json").string());
    Preset p;
    REQUIRE(LoadPreset(path, &p, &error));
    CHECK(p.scene == "midi");
    REQUIRE(p.params.size() == 4);
    for (const auto& [name, value] : MidiSnapshot().values) CHECK(p.params[name] == Approx(value).epsilon(1e-5));
    EffectSet e;
    REQUIRE(ParseEffectList(p.effects, &e, &error));
    CHECK(e == MidiSnapshot().effects);
    // No temporary file is left next to it.
    int files = 0;
    for (const auto& f : fs::directory_iterator(dir)) files += f.is_regular_file();
    CHECK(files == 1);
}

TEST_CASE("live_overlay presets: saving a scripted preset keeps its expressions, tempo and cues") {
    const fs::path dir = FreshDir(SDFVJ_LIVE_OUT, "overlay-save-scripted");
    WriteText(dir / "base.json", R"json({"scene": "midi", "bpm": 124, "params": {"twist": "0.4 + 0.3 * lfo_sine(beat / 4)", "scale": 1.0},
  "cues": [{"bar": 4, "set": {"scale": 1.5}, "over": 1}], "mapping": "mappings/akai_lpd8.toml"})json");
    PresetSnapshot s = MidiSnapshot();
    s.basePreset = (dir / "base.json").string();
    s.expressions["twist"] = "0.4 + 0.3 * lfo_sine(beat / 4)";
    std::string error;
    const std::string path = SavePresetAs(dir.string(), "scripted.json", s, &error);
    INFO(error);
    REQUIRE(!path.empty());
    Preset p;
    REQUIRE(LoadPreset(path, &p, &error));
    REQUIRE(p.automation.expressions.size() == 1);
    CHECK(p.automation.expressions[0].param == "twist");
    CHECK(p.automation.expressions[0].text == "0.4 + 0.3 * lfo_sine(beat / 4)");
    CHECK(p.params.count("twist") == 0);
    CHECK(p.params["scale"] == Approx(1.25f));
    CHECK(p.automation.bpm == 124.0);
    CHECK(p.automation.cues.size() == 1);
    CHECK(p.mapping == "mappings/akai_lpd8.toml");
}

TEST_CASE("live_overlay presets: a name that is not a plain file name is refused with a line, nothing written") {
    const fs::path dir = FreshDir(SDFVJ_LIVE_OUT, "overlay-save-bad");
    for (const std::string& bad : std::vector<std::string>{"", "../escape", "a/b", ".hidden", "with space", std::string(65, 'x')}) {
        std::string error;
        CHECK(SavePresetAs(dir.string(), bad, MidiSnapshot(), &error).empty());
        CHECK(error.find("not a plain file name") != std::string::npos);
        CHECK(error.find('\n') == std::string::npos);
    }
    CHECK(fs::is_empty(dir));
    CHECK(!fs::exists(dir.parent_path() / "escape.json"));
}

TEST_CASE("live_overlay keys: number keys pick presets by index in ListPresets, through the preset action path") {
    const std::vector<std::string> presets = ListPresets();
    REQUIRE(presets.size() >= 2);
    CHECK(PresetForNumberKey(1, presets) == presets[0]);
    CHECK(PresetForNumberKey(2, presets) == presets[1]);
    CHECK(PresetForNumberKey(0, presets).empty());
    CHECK(PresetForNumberKey((int)presets.size() + 1, presets).empty());
    CHECK(PresetForNumberKey(10, presets).empty());
    // What the session does with the key (ApplyOverlayActions): a preset request as from a pad.
    ShowOptions so;
    so.scene = "midi";
    so.path = "fragment";
    LiveState s;
    std::string err;
    REQUIRE(OpenLiveState(so, "", &s, &err));
    s.report.print = false;
    const std::string name = PresetForNumberKey(2, presets);
    s.actions.presetSelect.push_back(name);
    ApplyActions(s, 0.0);
    CHECK(s.currentPreset == name);
}

TEST_CASE("live_overlay monitor: keeps the last 12 events in order and describes MIDI bytes and OSC arguments") {
    EventMonitor m;
    std::vector<ControlEvent> events;
    for (int i = 0; i < 20; ++i) events.push_back(Midi(0xB0, 2, (uint8_t)i, i * 0.01));
    m.Add(events);
    m.Add({OscFloat("/x", 0.5f)});
    REQUIRE(m.recent.size() == 12);
    CHECK(m.recent.front().midi[2] == 9);
    CHECK(m.recent.back().address == "/x");
    CHECK(DescribeEvent(Midi(0xB0, 2, 127)).find("B0 02 7F  CC 2 ch1 = 127") != std::string::npos);
    CHECK(DescribeEvent(Midi(0x99, 36, 100)).find("note 36 ch10 on") != std::string::npos);
    CHECK(DescribeEvent(OscFloat("/x", 0.5f)).find("OSC   /x 0.5") != std::string::npos);
}

TEST_CASE("live_overlay sliders: each shows the controls mapped to it") {
    Mapping m;
    std::string text = "[[map]]\ncc = 2\nchannel = 1\ntarget = \"twist\"\n"
                       "[[map]]\nosc = \"/x\"\ntarget = \"twist\"\n"
                       "[[map]]\nnote = 36\naction = \"toggle\"\ntarget = \"scale\"\n";
    text += "[[map]]\ncc = 20\nchannel = 1\ntarget = 4\n";   // positional: the 4th input
    REQUIRE(ParseMapping(text, "t.toml", &m).ok);
    auto decl = [](const char* n) { ParamDecl d; d.name = n; return d; };
    const ParamState p = MakeParamState({decl("scale"), decl("twist"), decl("smoothness"), decl("glow")});
    CHECK(ControlsFor(m, p, 1) == "CC 2 ch1, OSC /x");
    CHECK(ControlsFor(m, p, 0) == "note 36");
    CHECK(ControlsFor(m, p, 2).empty());
    CHECK(ControlsFor(m, p, 3) == "CC 20 ch1");
}

TEST_CASE("live_overlay learn: the next moving control is taken from the drained events and appended to the mapping") {
    OverlayUi ui;
    ObserveEvents(ui, {Midi(0xB0, 5, 64)});           // not armed: only the monitor sees it
    CHECK(ui.learn.source.empty());
    ArmLearn(ui.learn, "twist");
    // A pad's single 127, an /sdfvj/ message and a first CC value do not count; a second value does.
    ObserveEvents(ui, {Midi(0xB0, 9, 127), OscFloat("/sdfvj/param/twist", 0.5f), Midi(0xB1, 7, 10)});
    CHECK(ui.learn.source.empty());
    ObserveEvents(ui, {Midi(0xB1, 7, 12), Midi(0xB0, 9, 0)});
    CHECK(ui.learn.source == "cc = 7\nchannel = 2");
    CHECK(ui.monitor.recent.size() == 6);

    LearnArm note;
    ArmLearn(note, "scale");
    CHECK(LearnFromEvent(note, Midi(0x90, 36, 0)).empty());   // note-off as velocity 0
    CHECK(LearnFromEvent(note, Midi(0x90, 36, 100)) == "note = 36\nchannel = 1\naction = \"toggle\"");
    LearnArm osc;
    ArmLearn(osc, "twist");
    CHECK(LearnFromEvent(osc, OscFloat("/fader1", 0.2f)) == "osc = \"/fader1\"");

    const fs::path dir = FreshDir(SDFVJ_LIVE_OUT, "overlay-learn");
    const fs::path mapping = dir / "m.toml";
    WriteText(mapping, "[profile]\nname = \"t\"\n\n[[map]]\ncc = 1\ntarget = \"scale\"\n");
    SceneInfo scene;
    std::string err;
    REQUIRE(FindScene("midi", &scene, &err));
    CHECK(AppendLearnedMapping(mapping.string(), "twist", ui.learn.source, scene.params) == "");
    Mapping m;
    REQUIRE(LoadMapping(mapping.string(), &m).ok);
    REQUIRE(m.entries.size() == 2);
    CHECK(m.entries[1].kind == SourceKind::Cc);
    CHECK(m.entries[1].number == 7);
    CHECK(m.entries[1].channel == 2);
    CHECK(m.entries[1].target == "twist");

    // A parameter the scene does not have is refused with a line; the file is byte-identical.
    const std::string before = Slurp(mapping);
    const std::string bad = AppendLearnedMapping(mapping.string(), "no_such_param", "cc = 8", scene.params);
    CHECK(bad.find("no_such_param") != std::string::npos);
    CHECK(Slurp(mapping) == before);
}

// ---------------------------------------------------------------------------------------------
// DrawOverlay itself, in an ImGui context with no window or GL: the mouse is set by hand.
// ---------------------------------------------------------------------------------------------

#include "headless_imgui.h"

namespace {

OverlayModel TwoParamModel() {
    OverlayModel m;
    m.scene = "midi";
    m.pathName = "fragment";
    m.params.push_back({"scale", "Scale", 0.5f, 2.0f, 1.0f, 1.0f, "CC 1 ch1", ""});
    m.params.push_back({"twist", "Twist", -3.0f, 3.0f, 0.7f, 0.7f, "", "0.4 + 0.3 * lfo_sine(beat / 4)"});
    m.presets = {"a.json", "b.json"};
    m.mappingFile = "m.toml";
    return m;
}


}  // namespace

TEST_CASE("live_overlay draw: a click on a checkbox returns the effect toggle, a scripted slider ignores clicks") {
    HeadlessImGui imgui;
    OverlayModel m = TwoParamModel();
    OverlayUi ui;
    REQUIRE(imgui.Frame(m, ui, ImVec2(-1, -1), false).Empty());   // nothing touched, nothing done

    ImVec2 ao;
    REQUIRE(imgui.Find(m, ui, ImGui::FindWindowByName("sdfvj")->GetID("ao"), &ao));
    CHECK(imgui.Frame(m, ui, ao, true).Empty());
    OverlayActions click = imgui.Frame(m, ui, ao, false);
    REQUIRE(click.effectToggles.size() == 1);
    CHECK(click.effectToggles[0] == std::make_pair(std::string("ao"), true));
    ImVec2 ssaa;   // anti-aliasing, a box of its own
    REQUIRE(imgui.Find(m, ui, ImGui::FindWindowByName("sdfvj")->GetID("ssaa"), &ssaa));
    imgui.Frame(m, ui, ssaa, true);
    OverlayActions aa = imgui.Frame(m, ui, ssaa, false);
    REQUIRE(aa.effectToggles.size() == 1);
    CHECK(aa.effectToggles[0] == std::make_pair(std::string("ssaa"), true));

    // The free slider: a click sets a target; the scripted one: nothing.
    ImVec2 scale, twist;
    REQUIRE(imgui.Find(m, ui, ParamWidgetId(0, "Scale"), &scale));
    OverlayActions set = imgui.Frame(m, ui, scale, true);
    imgui.Frame(m, ui, scale, false);
    REQUIRE(set.setTargets.size() == 1);
    CHECK(set.setTargets[0].first == 0);
    REQUIRE(imgui.Find(m, ui, ParamWidgetId(1, "Twist"), &twist));
    CHECK(imgui.Frame(m, ui, twist, true).setTargets.empty());
    CHECK(imgui.Frame(m, ui, ImVec2(twist.x + 40, twist.y), true).setTargets.empty());   // dragged
    CHECK(imgui.Frame(m, ui, twist, false).Empty());
    ImVec2 learn;
    REQUIRE(imgui.Find(m, ui, ParamWidgetId(0, "learn"), &learn));
    imgui.Frame(m, ui, learn, true);
    imgui.Frame(m, ui, learn, false);
    CHECK(ui.learn.param == "scale");
}

namespace {

// Everything the overlay wrote in one frame with the mouse away (OverlayUi::logText).
std::string OverlayText(HeadlessImGui& imgui, const OverlayModel& m, OverlayUi& ui) {
    ui.logText = true;
    imgui.Frame(m, ui, ImVec2(-1, -1), false);
    ui.logText = false;
    return ui.text;
}

}  // namespace

TEST_CASE("live_overlay times: the CPU graph and the GPU graph, or the GPU graph's n/a on a software renderer") {
    HeadlessImGui imgui;
    OverlayModel m = TwoParamModel();
    OverlayUi ui;
    for (int i = 0; i < 30; ++i) {
        ui.frames.Add(16.0f + (float)(i % 3));
        ui.gpu.Add(4.0f + (float)(i % 2));
    }
    imgui.Frame(m, ui, ImVec2(-1, -1), false);
    ImGuiWindow* w = ImGui::FindWindowByName("sdfvj");
    REQUIRE(w != nullptr);
    ImVec2 at;
    CHECK(imgui.Find(m, ui, w->GetID("##frames"), &at));
    CHECK(imgui.Find(m, ui, w->GetID("##gpu"), &at));
    std::string text = OverlayText(imgui, m, ui);
    INFO(text);
    CHECK(text.find("frame ms") != std::string::npos);
    CHECK(text.find("(GPU timer)") != std::string::npos);
    CHECK(text.find("avg 4.5 ms  max 5.0 ms") != std::string::npos);   // the GPU graph's caption

    // llvmpipe: no numbers that mean nothing, a line that says why.
    m.gpuTimesUnavailable = "software renderer";
    text = OverlayText(imgui, m, ui);
    CHECK(text.find("GPU ms: n/a (software renderer)") != std::string::npos);
    CHECK(text.find("(GPU timer)") == std::string::npos);
    CHECK_FALSE(imgui.Find(m, ui, w->GetID("##gpu"), &at));
    CHECK(imgui.Find(m, ui, w->GetID("##frames"), &at));
}

TEST_CASE("live_overlay effect costs: each measured effect shows its cost by its checkbox, and the button asks for a measurement") {
    HeadlessImGui imgui;
    OverlayModel m = TwoParamModel();
    m.effects.shadows = 2;
    m.effects.ao = true;
    m.effectCosts = {{"shadows", "+3.21 ms"}, {"ao", "+1.05 ms"}};
    m.effectCostNote = "median of 9 frame pairs (all on - one off), GPU timer queries";
    OverlayUi ui;
    const std::string text = OverlayText(imgui, m, ui);
    INFO(text);
    // ImGui's log puts a checkbox and the text after it (SameLine) on one line.
    CHECK(text.find("shadows +3.21 ms") != std::string::npos);
    CHECK(text.find("ao +1.05 ms") != std::string::npos);
    CHECK(text.find("median of 9 frame pairs") != std::string::npos);
    ImVec2 button;
    REQUIRE(imgui.Find(m, ui, ImGui::FindWindowByName("sdfvj")->GetID("measure costs"), &button));
    imgui.Frame(m, ui, button, true);
    CHECK(imgui.Frame(m, ui, button, false).measureCosts);
}
