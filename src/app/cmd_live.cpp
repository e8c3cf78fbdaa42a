// `sdfvj live`: a GLFW window, MIDI and OSC in, the performer's overlay on top.
//
// LiveSession owns what the show runs on (window, GL programs, devices, watcher, recorder) and
// its Frame() reads top to bottom: input -> mapping -> actions -> reloads -> program -> automation
// -> smoothing -> draw -> overlay -> present. The state a performer changes, and the stages that change it,
// live in live_session.h as plain data and free functions, tested without a window.
//
// Threads: input threads (RtMidi, liblo) only push onto the EventQueue; all GL and all state
// belong to this thread. Every stage runs inside Guard(): an exception that escapes a stage is a
// bug, and it is reported (once a second at most) while the show goes on with the last good state.
#include <epoxy/gl.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>

#include "app/commands.h"
#include "app/live_overlay.h"
#include "app/live_session.h"
#include "app/live_support.h"
#include "render/compile_worker.h"
#include "render/live_program.h"
#include "shader/watch.h"
#include "take/take.h"

namespace sdfvj {

namespace fs = std::filesystem;

namespace {

// The window and its GL context, Dear ImGui on it, and the optional compile thread's hidden
// window. Created first and destroyed last: every GL object of the session dies before it.
class LiveWindow {
public:
    ~LiveWindow() {
        PendingProgram::SetWorker(nullptr);
        worker_.reset();   // no compile may outlive the windows
        if (imgui_) {
            ImGui_ImplOpenGL3_Shutdown();
            ImGui_ImplGlfw_Shutdown();
            ImGui::DestroyContext();
        }
        if (compileWindow_) glfwDestroyWindow(compileWindow_);
        if (window_) glfwDestroyWindow(window_);
        if (glfw_) glfwTerminate();
    }
    bool Open(int w, int h, bool fullscreen, std::string* error) {
        if (!(glfw_ = glfwInit())) {
            *error = "no display (GLFW could not start); use `sdfvj render` for headless output";
            return false;
        }
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        window_ = glfwCreateWindow(w, h, "sdfvj", fullscreen ? glfwGetPrimaryMonitor() : nullptr, nullptr);
        if (!window_) {
            *error = "cannot open an OpenGL 4.5 core window on this display";
            return false;
        }
        glfwMakeContextCurrent(window_);
        glfwSwapInterval(1);
        std::fprintf(stderr, "GL: %s, %s\n", (const char*)glGetString(GL_RENDERER), (const char*)glGetString(GL_VERSION));
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;
        ImGui_ImplGlfw_InitForOpenGL(window_, true);
        ImGui_ImplOpenGL3_Init("#version 450");
        imgui_ = true;
        // Where it helps (Mesa; see PreferCompileThread), shader compiles run on a worker thread
        // with a hidden window's context that shares programs with this one, so a reload or a
        // variant switch does not stall frames. Elsewhere the driver's parallel compile is used.
        if (PreferCompileThread()) {
            glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
            compileWindow_ = glfwCreateWindow(1, 1, "sdfvj compiler", nullptr, window_);
            glfwWindowHint(GLFW_VISIBLE, GLFW_TRUE);
        }
        if (compileWindow_) {
            GLFWwindow* cw = compileWindow_;
            worker_ = std::make_unique<CompileWorker>(
                [cw] {
                    glfwMakeContextCurrent(cw);
                    return glfwGetCurrentContext() == cw;
                },
                false, [] { glfwMakeContextCurrent(nullptr); });
            if (worker_->Ok()) PendingProgram::SetWorker(worker_.get());
            else std::fprintf(stderr, "sdfvj live: no compile thread; shaders compile on the render thread\n");
        }
        return true;
    }
    GLFWwindow* Get() const { return window_; }
private:
    bool glfw_ = false, imgui_ = false;
    GLFWwindow* window_ = nullptr;
    GLFWwindow* compileWindow_ = nullptr;
    std::unique_ptr<CompileWorker> worker_;
};

class LiveSession {
public:
    LiveSession(const LiveOptions& o, LiveState state, GLFWwindow* window)
        : o_(o), state_(std::move(state)), window_(window), start_(std::chrono::steady_clock::now()),
          input_(InputConfig(o), queue_, [this] { return Now(); }) {}

    // Everything that may fail with a message before the first frame. False: exit code 2.
    bool Start(std::string* error);
    // One frame. False when the show is over (Esc, window closed, --seconds).
    bool Frame();
    void Finish();

private:
    static InputOptions InputConfig(const LiveOptions& o) {
        InputOptions io;
        io.midiPort = o.midi;
        io.oscPort = o.oscPort;
        io.oscFeedback = o.oscFeedback;
        return io;
    }
    double Now() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
    void ReadKeys();
    std::vector<ControlEvent> PollInput(double now);
    void Reload();
    void UpdateProgram();
    void LogParams(double now);
    void Draw(double now);
    void DrawOverlay();
    // The overlay's helpers (live_overlay.h): what it shows, and acting on what the performer did.
    OverlayModel OverlayModelNow();
    void ApplyOverlayActions(const OverlayActions& a, double now);
    void SavePreset(const std::string& name);
    void FinishLearn();
    void ToggleFullscreen();
    void Present();
    void SaveScreenshot(unsigned buffer);
    void Watch(const std::string& folder);
    // The last-resort guard around each stage: a bug reported, never a stopped show.
    template <class Stage> void Guard(const char* name, Stage&& stage) {
        try {
            stage();
        } catch (const std::exception& e) {
            ++internalErrors_;
            state_.report.Limited(Now(), {std::string("sdfvj live: internal error in ") + name + ": " + e.what() +
                                          " — the show goes on with the last good state"});
        } catch (...) {
            ++internalErrors_;
            state_.report.Limited(Now(), {std::string("sdfvj live: internal error in ") + name +
                                          " — the show goes on with the last good state"});
        }
    }

    const LiveOptions& o_;
    LiveState state_;
    GLFWwindow* window_;
    std::chrono::steady_clock::time_point start_;
    EventQueue queue_;
    InputSession input_;
    FolderWatcher watcher_;
    std::vector<std::string> watched_;   // canonical folders
    LiveProgram live_;
    FrameRenderer renderer_;
    // A scene change with a morph time fades from the old scene's frame to the new one's; the old
    // program stays alive (shared) and keeps rendering with its last values until the fade ends.
    struct Fade {
        std::shared_ptr<const Program> program;
        SceneInfo scene;
        std::vector<std::pair<std::string, float>> params;
        double start = 0.0, seconds = 0.0;
        Easing easing = Easing::Smooth;
    } fade_;
    std::shared_ptr<const Program> shown_;   // the program the last frame showed, and its scene
    SceneInfo shownScene_;
    FrameRenderer fadeRenderer_;
    Crossfade crossfade_;
    void StartFadeIfSceneChanged(double now);
    FrameInputs in_;
    TakeRecorder recorder_;
    Take rehearsal_;
    std::unique_ptr<ReplayCursor> replay_;
    std::unique_ptr<FILE, int (*)(FILE*)> paramLog_{nullptr, &std::fclose};
    std::string shownError_;
    bool overlay_ = true, tabWasDown_ = false, shotWritten_ = false;
    // The overlay's memory (monitor, frame graph, learn) and the keys it reads.
    OverlayUi ui_;
    double lastOverlay_ = -1.0, presetsListed_ = -1e9;
    std::vector<std::string> presets_;          // ListPresets(), refreshed twice a second
    bool f11WasDown_ = false, numberWasDown_[9] = {};
    int windowed_[4] = {0, 0, 0, 0};            // x, y, w, h before F11 went fullscreen
    double last_ = 0.0, fps_ = 0.0;
    bool dragWasDown_ = false, zeroWasDown_ = false;
    double dragX_ = 0.0, dragY_ = 0.0;
    int frame_ = 0, fbw_ = 0, fbh_ = 0;
    float renderScale_ = 1.0f;   // --render-scale and the overlay's resolution slider
    uint64_t internalErrors_ = 0;
};

bool LiveSession::Start(std::string* error) {
    // --log-params FILE appends one line per frame, "time name=value ...", with the values the
    // frame renders (after mapping and smoothing): for tests and for debugging a mapping. Line
    // buffered, so a reader sees each frame as soon as it is drawn.
    if (!o_.logParams.empty()) {
        paramLog_.reset(std::fopen(o_.logParams.c_str(), "a"));
        if (!paramLog_) {
            *error = "cannot write --log-params " + o_.logParams + ": " + std::strerror(errno);
            return false;
        }
        std::setvbuf(paramLog_.get(), nullptr, _IOLBF, 0);
    }
    overlay_ = !o_.hideOverlay;   // --hide-overlay: start as after Tab (clean screenshots)
    renderScale_ = (float)std::clamp(o_.renderScale, 0.25, 1.0);
    in_.quality = state_.show.quality;
    if (o_.show.path == "auto") {
        std::string log;
        state_.show.path = ProbeRenderPath(state_.show.scene, &log);
        std::fprintf(stderr, "%s\n", log.c_str());
    } else {
        state_.show.path = o_.show.path == "compute" ? RenderPath::Compute : RenderPath::Fragment;
    }
    state_.wanted.path = state_.show.path;
    // Hot reload: shaders, mappings and presets are watched as folders, and so are the folders of
    // the mapping and the preset on stage when they live elsewhere (--mapping/--preset FILE).
    for (const char* dir : {"shaders/lib", "shaders/scenes", "shaders/render", "mappings", "presets"})
        Watch(DataRoot() + "/" + dir);
    // The first program: a shader that does not compile keeps the window open with the error on
    // screen, and the next save that fixes it starts the show.
    live_.Request(state_.wanted);
    live_.Wait();
    for (const auto& line : input_.StatusLines()) std::fprintf(stderr, "%s\n", line.c_str());
    if (!o_.record.empty() && !recorder_.Open(o_.record, error))
        std::fprintf(stderr, "sdfvj live: not recording: %s\n", error->c_str());
    if (!o_.replay.empty()) {
        TakeReadResult r = ReadTake(o_.replay, &rehearsal_);
        if (!r.ok) std::fprintf(stderr, "sdfvj live: not replaying: %s\n", r.error.c_str());
        else replay_ = std::make_unique<ReplayCursor>(rehearsal_);
    }
    error->clear();
    last_ = Now();
    return true;
}

bool LiveSession::Frame() {
    glfwPollEvents();
    const double now = Now(), dt = now - last_;
    last_ = now;
    if (frame_ >= 2) fps_ = fps_ == 0 ? 1.0 / std::max(dt, 1e-6) : 0.95 * fps_ + 0.05 / std::max(dt, 1e-6);
    if ((o_.seconds > 0 && now >= o_.seconds) || glfwWindowShouldClose(window_) ||
        glfwGetKey(window_, GLFW_KEY_ESCAPE) == GLFW_PRESS)
        return false;
    ReadKeys();
    Guard("input", [&] { ApplyControl(state_, PollInput(now), now); });
    Guard("actions", [&] { ApplyActions(state_, now); });
    Guard("reload", [&] { Reload(); });
    Guard("program", [&] { UpdateProgram(); });
    Guard("automation", [&] { RunAutomation(state_, now, frame_); });
    StepSmoothing(state_.params, dt);
    Guard("log", [&] { LogParams(now); });
    Guard("draw", [&] { Draw(now); });
    Guard("overlay", [&] { DrawOverlay(); });
    Present();
    return true;
}

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
}

// Controllers, OSC and the rehearsal take all arrive through one queue; the recorder keeps
// every event the show applies.
std::vector<ControlEvent> LiveSession::PollInput(double now) {
    if (replay_)
        for (ControlEvent& e : replay_->Until(now)) queue_.Push(std::move(e));
    std::vector<ControlEvent> events = queue_.DrainUntil(now);
    ObserveEvents(ui_, events);   // the overlay's monitor, and learn when it is armed
    if (recorder_.IsOpen())
        for (const ControlEvent& e : events) recorder_.Record(e);
    return events;
}

// Saved files: the mapping and the preset on stage (live_session), shaders (LiveProgram).
void LiveSession::Reload() {
    for (const std::string& folder : state_.foldersToWatch) Watch(folder);
    state_.foldersToWatch.clear();
    const std::vector<std::string> changed = watcher_.Poll();
    ApplyFileChanges(state_, changed, Now());
    if (!(state_.wanted == live_.Key())) live_.Request(state_.wanted);
    live_.Update(changed);
    StartFadeIfSceneChanged(Now());
}

void LiveSession::StartFadeIfSceneChanged(double now) {
    if (live_.CurrentShared() == shown_) return;
    const MorphDesc& how = state_.show.preset.automation.morph;
    std::string error;
    if (shown_ && live_.Scene().path != shownScene_.path && how.seconds > 0 && how.easing != Easing::Cut &&
        crossfade_.Init(&error)) {
        fade_ = Fade{shown_, shownScene_, in_.params, now, how.seconds, how.easing};
    } else if (!error.empty()) {
        state_.report.Say("sdfvj live: " + error + " — scene changes cut instead of fading");
    }
    shown_ = live_.CurrentShared();
    shownScene_ = live_.Scene();
}

// The program on screen decides the parameters (its header may have changed), and its error
// the overlay's last line.
void LiveSession::UpdateProgram() {
    if (live_.Current()) FollowScene(state_, live_.Scene());
    if (state_.sendFeedback && state_.pendingTargets.empty()) {
        input_.SendFeedback(state_.params, state_.currentPreset);
        state_.sendFeedback = false;
    }
    if (live_.Error() != shownError_) {
        shownError_ = live_.Error();
        state_.report.Say(shownError_.empty() ? "shader reloaded" : shownError_);
    }
}

void LiveSession::LogParams(double now) {
    CopyParams(state_.params, &in_.params);
    if (!paramLog_) return;
    std::fprintf(paramLog_.get(), "%.4f", now);
    for (const auto& [name, value] : in_.params) std::fprintf(paramLog_.get(), " %s=%g", name.c_str(), value);
    std::fputc('\n', paramLog_.get());
}

void LiveSession::Draw(double now) {
    glfwGetFramebufferSize(window_, &fbw_, &fbh_);
    std::string error;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fbw_, fbh_);
    glClearColor(0.08f, 0.08f, 0.1f, 1.0f);   // until a first program compiles
    glClear(GL_COLOR_BUFFER_BIT);
    // The scene renders at renderScale_ of the window and is upscaled (linear) when it is smaller.
    const int rw = std::max(1, (int)std::lround(fbw_ * renderScale_)), rh = std::max(1, (int)std::lround(fbh_ * renderScale_));
    if (fbw_ <= 0 || fbh_ <= 0 || !live_.Current() || !renderer_.Resize(rw, rh, &error)) return;
    in_.time = now;
    in_.frame = frame_++;
    in_.beat = BeatPhase(state_, now);
    in_.bpm = (float)state_.automation.tempo.bpm;
    renderer_.Draw(*live_.Current(), live_.Scene(), in_);
    const double t = fade_.program ? (now - fade_.start) / fade_.seconds : 1.0;
    if (t < 1.0 && fadeRenderer_.Resize(rw, rh, &error)) {
        FrameInputs old = in_;
        old.params = fade_.params;
        fadeRenderer_.Draw(*fade_.program, fade_.scene, old);
        crossfade_.Draw(fadeRenderer_.Texture(), renderer_.Texture(), Ease(fade_.easing, t), 0, fbw_, fbh_);
    } else {
        fade_ = Fade{};   // done: the old program may go
        glBindFramebuffer(GL_READ_FRAMEBUFFER, renderer_.Framebuffer());
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        glBlitFramebuffer(0, 0, rw, rh, 0, 0, fbw_, fbh_, GL_COLOR_BUFFER_BIT, rw == fbw_ && rh == fbh_ ? GL_NEAREST : GL_LINEAR);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
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
    m.scene = live_.Scene().name;
    m.effectsText = DescribeEffects(live_.Key().effects);
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
    m.reportLines.assign(state_.report.recent.begin(), state_.report.recent.end());
    m.shaderError = shownError_;
    if (live_.Pending()) m.compiling = DescribeEffects(state_.wanted.effects);
    m.hasProgram = live_.Current() != nullptr;
    m.recording = recorder_.IsOpen();
    m.recorded = m.recording ? recorder_.Recorded() : 0;
    m.mappingFile = state_.mappingFile;
    return m;
}

// Preset loads and effect toggles go through ApplyActions, as a pad or /sdfvj/preset and
// /sdfvj/effect/<name> would; this frame's own actions were applied already and are put back.
void LiveSession::ApplyOverlayActions(const OverlayActions& a, double now) {
    if (a.renderScale > 0.0f) renderScale_ = std::clamp(a.renderScale, 0.25f, 1.0f);
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
    if (!ui_.learn.Armed() || ui_.learn.source.empty()) return;
    const std::string error = AppendLearnedMapping(state_.mappingFile, ui_.learn.param, ui_.learn.source, state_.params.decls);
    const std::string control = ui_.learn.source.substr(0, ui_.learn.source.find('\n'));
    state_.report.Say(error.empty() ? "learned: " + control + " -> " + ui_.learn.param + ", written to " + state_.mappingFile
                                    : error);
    ArmLearn(ui_.learn, "");
}

void LiveSession::SaveScreenshot(unsigned buffer) {
    if (fbw_ <= 0 || fbh_ <= 0) return;
    std::vector<uint8_t> rgba((size_t)fbw_ * fbh_ * 4), flipped(rgba.size());
    glReadBuffer(buffer);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, fbw_, fbh_, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    for (int y = 0; y < fbh_; ++y)
        std::copy_n(&rgba[(size_t)(fbh_ - 1 - y) * fbw_ * 4], (size_t)fbw_ * 4, &flipped[(size_t)y * fbw_ * 4]);
    std::string err;
    if (!WritePng(o_.screenshot, fbw_, fbh_, flipped, &err)) std::fprintf(stderr, "sdfvj live: %s\n", err.c_str());
    shotWritten_ = true;
}

void LiveSession::Present() {
    if (!o_.screenshot.empty() && o_.seconds > 0 && Now() + 0.05 >= o_.seconds) SaveScreenshot(GL_BACK);
    glfwSwapBuffers(window_);
}

void LiveSession::Finish() {
    // Slow frames (software GL) or a closed window can end the show before Present() took the
    // screenshot: then the front buffer holds the last frame shown.
    if (!o_.screenshot.empty() && !shotWritten_ && frame_ > 0) SaveScreenshot(GL_FRONT);
    if (recorder_.IsOpen()) {
        recorder_.Close(Now());
        std::fprintf(stderr, "recorded %zu events to %s\n", recorder_.Recorded(), o_.record.c_str());
    }
    if (internalErrors_ > 0)
        std::fprintf(stderr, "sdfvj live: %llu internal errors were caught during the show (see above)\n",
                     (unsigned long long)internalErrors_);
}

void LiveSession::Watch(const std::string& dir) {
    std::error_code ec;
    const std::string canonical = fs::weakly_canonical(dir, ec).string();
    if (ec || std::find(watched_.begin(), watched_.end(), canonical) != watched_.end()) return;
    std::string error;
    if (watcher_.Watch(canonical, &error)) watched_.push_back(canonical);
    else state_.report.Say("sdfvj live: " + error);
}

}  // namespace

int RunLive(const LiveOptions& o) {
    std::string error;
    int w = 0, h = 0;
    LiveState state;
    if (!ParseSize(o.size, &w, &h, &error) || !OpenLiveState(o.show, o.mapping, &state, &error)) {
        std::fprintf(stderr, "sdfvj live: %s\n", error.c_str());
        return 2;
    }
    LiveWindow window;
    if (!window.Open(w, h, o.fullscreen, &error)) {
        std::fprintf(stderr, "sdfvj live: %s\n", error.c_str());
        return 2;
    }
    LiveSession session(o, std::move(state), window.Get());   // GL objects die before the window
    if (!session.Start(&error)) {
        std::fprintf(stderr, "sdfvj live: %s\n", error.c_str());
        return 2;
    }
    while (session.Frame()) {
    }
    session.Finish();
    return 0;
}

}  // namespace sdfvj
