// `sdfvj live`: the keys (Tab, F11, 1-9, mouse orbit) and the overlay's glue: the model it draws
// from, and acting on what the performer did in it (live_overlay.h draws it).
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "app/live_app.h"
#include "app/live_support.h"

namespace sdfvj {

namespace fs = std::filesystem;

// Keys the performer uses without the mouse. Ignored while the overlay edits text (a preset
// name), so typing "set2" does not switch presets.
void LiveSession::ReadKeys() {
    const bool typing = ImGui::GetCurrentContext() && ImGui::GetIO().WantTextInput;
    auto pressed = [&](int key, bool& wasDown) {
        const bool down = glfwGetKey(window_, key) == GLFW_PRESS;
        const bool edge = down && !wasDown && !typing;
        wasDown = down;
        return edge;
    };
    if (pressed(GLFW_KEY_TAB, tabWasDown_)) overlay_ = !overlay_;
    // Mouse drag orbits the camera around the scene's target (where the overlay does not want the
    // mouse); 0 puts the scene's own camera back.
    double mx = 0, my = 0;
    glfwGetCursorPos(window_, &mx, &my);
    const bool dragging = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS &&
                          !(ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse);
    if (dragging && dragWasDown_) {
        in_.orbitYaw -= float(mx - dragX_) * 0.01f;
        in_.orbitPitch = std::clamp(in_.orbitPitch + float(my - dragY_) * 0.01f, -1.5f, 1.5f);
    }
    dragWasDown_ = dragging;
    dragX_ = mx;
    dragY_ = my;
    if (pressed(GLFW_KEY_0, zeroWasDown_)) in_.orbitYaw = in_.orbitPitch = 0.0f;
    if (pressed(GLFW_KEY_F11, f11WasDown_)) ToggleFullscreen();
    for (int n = 1; n <= 9; ++n) {
        if (!pressed(GLFW_KEY_0 + n, numberWasDown_[n - 1])) continue;
        const std::string name = PresetForNumberKey(n, ListPresets());
        if (name.empty()) state_.report.Say("sdfvj live: key " + std::to_string(n) + ": no preset " + std::to_string(n) +
                                            " in presets/ (see `sdfvj list`)");
        else ApplyOverlayActions(OverlayActions{{}, name, {}, {}}, Now());
    }
}

// F11: the primary monitor at its own mode, and back to the window as it was.
void LiveSession::ToggleFullscreen() {
    if (glfwGetWindowMonitor(window_)) {
        int w = windowed_[2], h = windowed_[3];
        if (w <= 0 || h <= 0) {   // started with --fullscreen: the --size it was asked for
            std::string err;
            if (!ParseSize(o_.size, &w, &h, &err)) w = 1280, h = 720;
        }
        glfwSetWindowMonitor(window_, nullptr, windowed_[0], windowed_[1], w, h, GLFW_DONT_CARE);
        state_.report.Say("F11: windowed " + std::to_string(w) + "x" + std::to_string(h));
        return;
    }
    GLFWmonitor* monitor = glfwGetPrimaryMonitor();
    const GLFWvidmode* mode = monitor ? glfwGetVideoMode(monitor) : nullptr;
    if (!mode) {
        state_.report.Say("sdfvj live: F11: no monitor to go fullscreen on");
        return;
    }
    glfwGetWindowPos(window_, &windowed_[0], &windowed_[1]);
    glfwGetWindowSize(window_, &windowed_[2], &windowed_[3]);
    glfwSetWindowMonitor(window_, monitor, 0, 0, mode->width, mode->height, mode->refreshRate);
    const char* name = glfwGetMonitorName(monitor);
    state_.report.Say("F11: fullscreen " + std::to_string(mode->width) + "x" + std::to_string(mode->height) + " on " +
                      (name ? name : "the primary monitor"));
}

// The overlay: what the performer needs, nothing the audience should see (Tab hides it). It is
// drawn from a copy of the show (OverlayModelNow) and returns what the performer did, which is
// applied here through the same paths as pads and OSC.
void LiveSession::DrawOverlay() {
    const double now = Now();
    if (lastOverlay_ >= 0) ui_.frames.Add(float((now - lastOverlay_) * 1000.0));
    lastOverlay_ = now;
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    OverlayActions actions;
    if (overlay_) actions = sdfvj::DrawOverlay(OverlayModelNow(), ui_);
    ImGui::Render();
    glViewport(0, 0, fbw_, fbh_);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ApplyOverlayActions(actions, now);
    FinishLearn();
}

OverlayModel LiveSession::OverlayModelNow() {
    OverlayModel m;
    m.scene = SceneOnScreen().name;
    m.effectsText = DescribeEffects(KeyOnScreen().effects);
    m.pathName = RenderPathName(state_.show.path);
    m.fps = (float)fps_;
    m.width = fbw_;
    m.height = fbh_;
    m.renderScale = renderScale_;
    const ParamState& params = state_.params;
    const Automation& scripts = state_.automation.automation;
    for (size_t i = 0; i < params.decls.size(); ++i) {
        const ParamDecl& d = params.decls[i];
        m.params.push_back({d.name, d.label.empty() ? d.name : d.label, d.minValue, d.maxValue, params.value[i],
                            params.target[i], ControlsFor(state_.mapping, params, (int)i),
                            scripts.Scripted(d.name) ? scripts.ExpressionText(d.name) : std::string()});
    }
    if (Now() - presetsListed_ > 0.5) {   // a directory listing, not every frame
        presets_ = ListPresets();
        presetsListed_ = Now();
    }
    m.presets = presets_;
    m.currentPreset = state_.currentPreset;
    m.effects = state_.wanted.effects;
    m.statusLines = input_.StatusLines();
    // --sync mtc / a --forward leader: locked, holding, freewheeling or stopped, kept in view.
    if (const std::string sync = LiveSyncStatus(sync_, Now()); !sync.empty()) m.statusLines.push_back("sync: " + sync);
    if (const std::string budget = FrameBudgetStatus(budget_); !budget.empty()) m.statusLines.push_back(budget);
    m.reportLines.assign(state_.report.recent.begin(), state_.report.recent.end());
    m.shaderError = shownError_;
    if (servers_ ? servers_->Servers().Building() : live_.Pending()) m.compiling = DescribeEffects(state_.wanted.effects);
    if (live_.Current() && live_.Current()->Origin().literalTier)
        m.statusLines.push_back("shader: retuned numbers read from uniforms until the optimized program is in");
    m.hasProgram = HasProgram();
    m.recording = recorder_.IsOpen();
    m.recorded = m.recording ? recorder_.Recorded() : 0;
    m.mappingFile = state_.mappingFile;
    if (softwareGl_) m.gpuTimesUnavailable = "software renderer";
    // Costs belong to the program they were measured on: shown only while it is on screen.
    if (costs_.Started() && costs_.effects == KeyOnScreen().effects) {
        for (const EffectCostRow& r : costs_.rows) m.effectCosts.emplace_back(r.name, EffectCostText(r, costs_));
        m.effectCostNote = EffectCostNote(costs_);
    }
    return m;
}

// Preset loads and effect toggles go through ApplyActions, as a pad or /sdfvj/preset and
// /sdfvj/effect/<name> would; this frame's own actions were applied already and are put back.
void LiveSession::ApplyOverlayActions(const OverlayActions& a, double now) {
    if (a.renderScale > 0.0f) renderScale_ = std::clamp(a.renderScale, 0.25f, 2.0f);
    if (a.measureCosts) StartEffectCosts(costs_, KeyOnScreen().effects, 9, softwareGl_ || servers_);   // a server times its own draws
    for (const auto& [index, value] : a.setTargets)
        if (index >= 0 && (size_t)index < state_.params.decls.size()) SetParamTarget(state_.params, index, value);
    if (!a.loadPreset.empty() || !a.effectToggles.empty()) {
        MappingActions frameActions = std::move(state_.actions);
        state_.actions = MappingActions{};
        if (!a.loadPreset.empty()) state_.actions.presetSelect.push_back(a.loadPreset);
        state_.actions.effectToggles = a.effectToggles;
        ApplyActions(state_, now);
        state_.actions = std::move(frameActions);
    }
    if (!a.savePreset.empty()) SavePreset(a.savePreset);
}

// Save and save-as: the values the performer set (targets) and the scripts of the preset on
// stage, as presets/NAME.json. A save over the preset on stage reloads it (the watcher).
void LiveSession::SavePreset(const std::string& name) {
    PresetSnapshot snap;
    const std::vector<std::string> scenes = ListScenes();
    const std::string& sceneName = state_.show.scene.name;
    snap.scene = std::find(scenes.begin(), scenes.end(), sceneName) != scenes.end() ? sceneName : state_.show.scene.path;
    const Automation& scripts = state_.automation.automation;
    for (size_t i = 0; i < state_.params.decls.size(); ++i) {
        const std::string& param = state_.params.decls[i].name;
        snap.values.emplace_back(param, state_.params.target[i]);
        if (scripts.Scripted(param)) snap.expressions[param] = scripts.ExpressionText(param);
    }
    snap.effects = state_.wanted.effects;
    snap.basePreset = state_.presetFile;
    std::string error;
    const std::string path = SavePresetAs((fs::path(DataRoot()) / "presets").string(), name, snap, &error);
    state_.report.Say(path.empty() ? "sdfvj live: " + error : "saved " + path);
    presetsListed_ = -1e9;
}

// Learn found a control: the mapping file gets its [[map]] entry and the watcher reloads it.
void LiveSession::FinishLearn() {
    const std::string line = sdfvj::FinishLearn(ui_.learn, state_.mappingFile, state_.params.decls);
    if (!line.empty()) state_.report.Say(line);
}

}  // namespace sdfvj
