// Learn through the overlay with a real MIDI control: the overlay's learn button is clicked
// (ImGui input, headless_imgui.h), real CCs go from a fake device (jack_midi_out.h) through JACK's dummy server
// (ctest fixture `jackd`) into an InputSession's virtual port, and the frame's stages of `live`
// run over them in order: drain the queue, ObserveEvents (learn), ApplyControl, the learn stage
// (FinishLearn writes the mapping file), the folder watcher, ApplyFileChanges (reload).

#include "../control/jack_midi_out.h"
#include <unistd.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "app/live_overlay.h"
#include "app/live_session.h"
#include "headless_imgui.h"
#include "live_util.h"
#include "shader/watch.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

double Now() {
    static const auto t0 = std::chrono::steady_clock::now();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// What the overlay shows of the show's parameters (as LiveSession::OverlayModelNow builds it).
OverlayModel ModelOf(const LiveState& s) {
    OverlayModel m;
    m.scene = s.show.scene.name;
    for (size_t i = 0; i < s.params.decls.size(); ++i) {
        const ParamDecl& d = s.params.decls[i];
        m.params.push_back({d.name, d.label.empty() ? d.name : d.label, d.minValue, d.maxValue, s.params.value[i],
                            s.params.target[i], ControlsFor(s.mapping, s.params, (int)i), ""});
    }
    m.mappingFile = s.mappingFile;
    return m;
}

}  // namespace

TEST_CASE("live_learn jack: the learn button, a real CC through JACK, the mapping file, and the next CC moves the parameter") {
    const fs::path dir = FreshDir(SDFVJ_LIVE_OUT, "learn-jack");
    const std::string mapping = (dir / "m.toml").string();
    std::ofstream(mapping) << "[profile]\nname = \"learn test\"\n\n[[map]]\ncc = 1\ntarget = \"scale\"\n";
    ShowOptions so;
    so.scene = "midi";
    so.path = "fragment";
    LiveState state;
    std::string error;
    REQUIRE(OpenLiveState(so, mapping, &state, &error));
    state.report.print = false;
    const int twist = FindParam(state.params, "twist");
    REQUIRE(twist >= 0);
    FolderWatcher watcher;   // as `live` watches the mapping's folder
    REQUIRE(watcher.Watch(dir.string(), &error));

    const std::string vname = "sdfvj-learn-" + std::to_string(getpid());
    EventQueue queue;
    InputOptions io;
    io.midiPort = "no-controller-here";
    io.virtualPortName = vname;
    io.oscPort = -1;
    io.log = false;
    InputSession input(io, queue, &Now);
    INFO(input.StatusLines()[0]);
    REQUIRE(input.StatusLines()[0].rfind("MIDI (JACK)", 0) == 0);
    MidiOutPtr outOwner = MakeMidiOut("learn-test-out-" + std::to_string(getpid()));
    JackMidiOut& out = *outOwner;
    bool connected = false;
    for (unsigned i = 0; i < out.getPortCount() && !connected; ++i)
        if (out.getPortName(i).find(vname) != std::string::npos) {
            out.openPort(i, "out");
            connected = true;
        }
    REQUIRE(connected);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));   // let JACK finish the connection
    auto cc = [&](unsigned char number, unsigned char value) {
        std::vector<unsigned char> msg = {0xB0, number, value};
        out.sendMessage(&msg);
    };

    // One `live` frame without the drawing: the stages in the order Frame() runs them.
    HeadlessImGui imgui;
    OverlayUi ui;
    std::vector<std::string> lines;
    auto frame = [&] {
        const double now = Now();
        std::vector<ControlEvent> events = queue.DrainUntil(now);
        ObserveEvents(ui, events);
        ApplyControl(state, events, now);
        ApplyFileChanges(state, watcher.Poll(), now);
        imgui.Frame(ModelOf(state), ui, ImVec2(-1, -1), false);
        const std::string line = FinishLearn(ui.learn, state.mappingFile, state.params.decls);
        if (!line.empty()) lines.push_back(line);
    };

    // The performer clicks "learn" next to Twist.
    frame();
    ImVec2 learn;
    REQUIRE(imgui.Find(ModelOf(state), ui, ParamWidgetId(twist, "learn"), &learn));
    imgui.Frame(ModelOf(state), ui, learn, true);
    imgui.Frame(ModelOf(state), ui, learn, false);
    REQUIRE(ui.learn.param == "twist");

    // ... and turns a knob that sends CC 21: two different values make it a continuous control.
    cc(21, 10);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    cc(21, 14);
    REQUIRE(PollFor(5.0, [&] {
        frame();
        return !lines.empty();
    }));
    INFO(lines[0]);
    CHECK(lines[0] == "learned: cc = 21 -> twist, written to " + mapping);
    CHECK_FALSE(ui.learn.Armed());
    Mapping written;
    REQUIRE(LoadMapping(mapping, &written).ok);
    REQUIRE(written.entries.size() == 2);
    CHECK(written.entries[1].kind == SourceKind::Cc);
    CHECK(written.entries[1].number == 21);
    CHECK(written.entries[1].target == "twist");

    // The watcher sees the new file and the show reloads it; the overlay now lists CC 21 by Twist.
    REQUIRE(PollFor(5.0, [&] {
        frame();
        return state.mapping.entries.size() == 2;
    }));
    CHECK(ModelOf(state).params[(size_t)twist].controls.find("CC 21") != std::string::npos);

    // The next CC moves the parameter: 127 is the top of its range, 0 the bottom.
    const float before = state.params.target[(size_t)twist];
    cc(21, 127);
    REQUIRE(PollFor(5.0, [&] {
        frame();
        return state.params.target[(size_t)twist] != before;
    }));
    CHECK(state.params.target[(size_t)twist] == Approx(3.0f));
    cc(21, 0);
    REQUIRE(PollFor(5.0, [&] {
        frame();
        return state.params.target[(size_t)twist] < 0.0f;
    }));
    CHECK(state.params.target[(size_t)twist] == Approx(-3.0f));
}
