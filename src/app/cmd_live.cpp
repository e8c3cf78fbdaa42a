// `sdfvj live`: a GLFW window, MIDI and OSC in, the performer's overlay on top.
//
// LiveSession owns what the show runs on (window, GL programs, devices, watcher, recorder) and
// its Frame() reads top to bottom: input -> mapping -> actions -> reloads -> program -> automation
// -> smoothing -> draw -> overlay -> present. The state a performer changes, and the stages that change it,
// live in live_session.h as plain data and free functions, tested without a window.
//
// Declarations in live_app.h; the keys and the overlay's glue in live_session_ui.cpp.
//
// Threads: input threads (RtMidi, liblo) only push onto the EventQueue; all GL and all state
// belong to this thread. Every stage runs inside Guard(): an exception that escapes a stage is a
// bug, and it is reported (once a second at most) while the show goes on with the last good state.

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iterator>
#include <memory>

#include "app/live_app.h"
#include "app/live_support.h"
#include "audio/wav.h"

namespace sdfvj {

namespace fs = std::filesystem;

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
    renderScale_ = (float)std::clamp(o_.renderScale, 0.25, 2.0);
    softwareGl_ = IsSoftwareRenderer();
    if (const char* keep = std::getenv("SDFVJ_KEEP_SIZES"); keep && *keep >= '0' && *keep <= '9' && !keep[1]) keepSizes_ = *keep - '0';
    for (FrameRenderer* r : {&renderer_, &fadeRenderer_, &postInput_}) r->SetKeptSizes(keepSizes_);
    in_.quality = state_.show.quality;
    std::string budgetError;
    if (o_.frameBudgetMs > 0) {
        if (!StartLiveFrameBudget(&budget_, o_.frameBudgetMs, o_.budgetFloor, state_.show.scene.name, &in_.quality,
                                  &renderScale_, &budgetError))
            state_.report.Say("sdfvj live: no frame budget: " + budgetError);
        else {
            char line[256];
            std::snprintf(line, sizeof line, "frame budget %.3g ms: starts at %s, the best of %zu settings on the front above the floor",
                          o_.frameBudgetMs, budget_.front[budget_.current].label.c_str(), budget_.front.size());
            state_.report.Say(line);
            // Drawn ahead where a new target costs (not on Mesa's software rasterizers, where the extra
            // frames cost more than the allocations they save); SDFVJ_SCALES_AHEAD=0|1 forces.
            scalesAheadOn_ = EnvSwitch("SDFVJ_SCALES_AHEAD", !softwareGl_);
        }
    }
    if (o_.show.path == "auto" && !state_.show.isfScene) {
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
    // A save that only retunes numbers shows in the next frame (the literal tier). Its build runs
    // beside the show: by default where the GPU compiles beside the frame, not on llvmpipe, where
    // it would take the CPU the frames need (SDFVJ_LITERAL_TIER=1|0 forces it).
    live_.SetLiteralTier(!softwareGl_);
    // A save that edits what the scene's functions compute shows in the next frame too, drawn by
    // the scene's evaluator program (built behind the show; live_program_eval.cpp) until its
    // optimized program is built. Off: measured on an NVIDIA H100 its interpreted frame takes
    // 540-610 ms at 1080p, so a save's first image comes later than the quick tier's and the show
    // stalls until the optimized program (docs/performance.md "Session 45"; llvmpipe: "Session 44").
    // SDFVJ_EVALUATOR_TIER=1 turns it on.
    live_.SetEvaluatorTier(false);
    live_.SetPrimePrefetched(o_.warmAhead);   // --warm-ahead: a pad hit shows its variant in one frame
    if (o_.renderProcess && !state_.show.isfScene) StartServers();
    if (!servers_ && !state_.show.isfScene) {   // an ISF generator is the post chain's first stage instead
        live_.Request(state_.wanted);
        live_.Wait();
    }
    for (const auto& line : input_.StatusLines()) std::fprintf(stderr, "%s\n", line.c_str());
    if (!o_.audio.empty()) {   // no server: one line, and the show goes on without audio
        AudioInputDesc audio;
        if (o_.audio != "in") audio.connect = o_.audio;
        if (!o_.record.empty()) audio.recordWav = TakeWavPath(o_.record);   // render --replay feeds ISF audio inputs from it
        std::string status;
        audio_ = AudioInput::Open(audio, &status);
        if (!status.empty()) std::fprintf(stderr, "%s\n", status.c_str());
    }
    if (!o_.record.empty() && !recorder_.Open(o_.record, error))
        std::fprintf(stderr, "sdfvj live: not recording: %s\n", error->c_str());
    if (!o_.replay.empty()) {
        TakeReadResult r = ReadTake(o_.replay, &rehearsal_);
        if (!r.ok) std::fprintf(stderr, "sdfvj live: not replaying: %s\n", r.error.c_str());
        else replay_ = std::make_unique<ReplayCursor>(rehearsal_);
    }
    if (!ParseSyncMode(o_.sync, &sync_.mode, error)) return false;
    if (!OpenLiveForward(o_.forward, &forward_, error)) return false;
    if (sync_.mode != LiveSync::Mode::Wall) state_.report.Say("sdfvj live: " + LiveSyncStatus(sync_, 0.0));
    error->clear();
    last_ = Now();
    return true;
}

bool LiveSession::Frame() {
    hitch_.Begin(Now());
    Guard("window events", [] { glfwPollEvents(); });
    const double wall = Now(), dt = wall - last_;
    last_ = wall;
    if (frame_ >= 2) fps_ = fps_ == 0 ? 1.0 / std::max(dt, 1e-6) : 0.95 * fps_ + 0.05 / std::max(dt, 1e-6);
    bool timeUp = o_.seconds > 0 && wall >= o_.seconds;
    // --screenshot promises the last frame: a show whose first program is still compiling when
    // --seconds ends (software GL on a loaded machine) runs on until it has drawn one, at most
    // kScreenshotGraceS more, and says so.
    constexpr double kScreenshotGraceS = 30.0;
    if (timeUp && !o_.screenshot.empty() && frame_ == 0 && wall < o_.seconds + kScreenshotGraceS) {
        if (!shotWaitSaid_)
            std::fprintf(stderr, "sdfvj live: no frame drawn yet after --seconds %g; running on until one is, for --screenshot\n",
                         o_.seconds);
        shotWaitSaid_ = true;
        timeUp = false;
    }
    if (timeUp || glfwWindowShouldClose(window_) || glfwGetKey(window_, GLFW_KEY_ESCAPE) == GLFW_PRESS) return false;
    ReadKeys();
    double now = wall;   // the show clock: the wall clock, or a master's timecode (--sync mtc)
    Guard("input", [&] {
        std::vector<ControlEvent> events = PollInput(wall);
        now = SyncShowClock(&events, wall);
        DropPresetStatesOnStage(&events, state_.currentPreset);   // a leader's state for the preset on stage
        ForwardBeforeControl(forward_, state_);
        ApplyControl(state_, events, now);
    });
    Guard("actions", [&] {
        ApplyActions(state_, now);
        ForwardAfterActions(forward_, state_, now);   // --forward: to the follower nodes
    });
    Guard("reload", [&] { Reload(); });
    Guard("program", [&] { UpdateProgram(); });
    Guard("automation", [&] { RunAutomation(state_, now, frame_); });
    StepSmoothing(state_.params, dt);
    Guard("follow", [&] {   // a --forward leader heard: its values; a leader: this frame to the followers
        FollowLeaderValues(sync_, state_.params);
        // The tempo this frame draws with (DrawScene, the post chain) and forwards: a follower's
        // is its leader's.
        in_.beat = BeatPhase(state_, now);
        in_.bpm = (float)state_.automation.tempo.bpm;
        LeaderTempo(sync_, &in_.beat, &in_.bpm);
        ForwardFrame(forward_, state_, now, LiveSyncRunning(sync_), in_.beat, in_.bpm);
    });
    Guard("log", [&] { LogParams(now); });
    Guard("draw", [&] { Draw(now); });
    Guard("costs", [&] { MeasureEffectCosts(); });
    Guard("overlay", [&] { DrawOverlay(); });
    Guard("present", [&] { Present(); });
    Guard("servers", [&] { if (servers_) servers_->FrameDone(); });   // the servers this frame retired end in the gap
    // The terminal only: the overlay has its frame-time graph, and its report stays the show's messages.
    if (std::string line; hitch_.End(Now(), &line)) std::fprintf(stderr, "%s\n", line.c_str());
    return true;
}

// Controllers, OSC and the rehearsal take all arrive through one queue; the recorder keeps
// every event the show applies.
std::vector<ControlEvent> LiveSession::PollInput(double now) {
    if (replay_ && !LiveSyncFollows(sync_)) {   // else the take plays on the show clock (SyncShowClock)
        for (ControlEvent& e : replay_->Until(now)) queue_.Push(std::move(e));
        takeAt_ = now;
    }
    if (audio_) queue_.Push(AudioFeatureEvent(audio_->Poll(now), now));   // mapping and recorder, like a knob
    std::vector<ControlEvent> events = queue_.DrainUntil(now);
    // The overlay's monitor, learn when it is armed, and the recorder: a leader's clock frames
    // (one a frame) are the show clock's only (SyncShowClock).
    if (std::any_of(events.begin(), events.end(), IsLeaderClock)) {
        std::vector<ControlEvent> seen;
        std::copy_if(events.begin(), events.end(), std::back_inserter(seen), [](const ControlEvent& e) { return !IsLeaderClock(e); });
        ObserveEvents(ui_, seen);
    } else {
        ObserveEvents(ui_, events);
    }
    if (recorder_.IsOpen())
        for (const ControlEvent& e : events)
            if (!IsLeaderClock(e)) recorder_.Record(e);
    return events;
}

// --sync mtc or a --forward leader heard: the master's time is the show clock (live_sync.h); what
// it says goes to the overlay and stderr once. The rehearsal take plays on it: a jump back starts
// the take over.
double LiveSession::SyncShowClock(std::vector<ControlEvent>* events, double wall) {
    std::vector<std::string> say;
    const double show = LiveSyncStep(sync_, events, wall, &say);
    for (const std::string& line : say)   // a leader is the network's: at most a line a second
        if (line.rfind("sdfvj live: leader", 0) == 0 || line.rfind("sdfvj live: /sdfvj/clock", 0) == 0)
            state_.report.Limited(wall, {line}, "leader");
        else
            state_.report.Say(line);
    if (replay_ && LiveSyncFollows(sync_)) {
        if (show < takeAt_) replay_ = std::make_unique<ReplayCursor>(rehearsal_);
        for (ControlEvent& e : replay_->Until(show)) {
            e.time = show;
            events->push_back(std::move(e));
        }
        takeAt_ = show;
    }
    return show;
}

// Saved files: the mapping and the preset on stage (live_session), shaders (LiveProgram).
void LiveSession::Reload() {
    for (const std::string& folder : state_.foldersToWatch) Watch(folder);
    state_.foldersToWatch.clear();
    const std::vector<std::string> changed = watcher_.Poll();
    // Each part its own stage (--hitch-ms says which one took a long frame's time).
    Guard("reload: files", [&] { ApplyFileChanges(state_, changed, Now()); });
    if (servers_) {   // --render-process: builds go to spare servers
        int w = 0, h = 0;
        glfwGetFramebufferSize(window_, &w, &h);
        std::vector<std::string> say;
        Guard("reload: morph", [&] { PrepareServerMorph(); });
        Guard("reload: render processes", [&] { servers_->Update(state_.wanted, changed, Scaled(w), Scaled(h), &say); });
        for (const std::string& line : say) state_.report.Say(line);
        Guard("reload: fade", [&] { FadeServersIfSceneChanged(Now()); });
        Guard("reload: prefetch", [&] { PrefetchReachable(Now()); });
        Guard("reload: post", [&] { ReloadPost(changed); });
        return;
    }
    if (!(state_.wanted == live_.Key()) && !state_.show.isfScene) {
        Guard("reload: morph", [&] { PrepareFieldMorph(); });
        Guard("reload: program asked", [&] { live_.Request(state_.wanted); });
    }
    Guard("reload: program", [&] { live_.Update(changed); });
    Guard("reload: prefetch", [&] { PrefetchReachable(Now()); });
    Guard("reload: post", [&] { ReloadPost(changed); });
    Guard("reload: fade", [&] { StartFadeIfSceneChanged(Now()); });
}

void LiveSession::StartFadeIfSceneChanged(double now) {
    if (live_.CurrentShared() == shown_) return;
    const MorphDesc& how = state_.show.preset.automation.morph;
    std::string error;
    if (shown_ && live_.Scene().path != shownScene_.path && how.seconds > 0 && how.easing != Easing::Cut &&
        crossfade_.Init(&error)) {
        fade_ = Fade{shown_, shownScene_, in_.params, now, how.seconds, how.easing};
        fade_.field = FadeMorphsFields();
        fade_.waiting = fade_.field && fieldMorph_.Poll() != FieldMorph::State::Ready;
    } else if (!error.empty()) {
        state_.report.Say("sdfvj live: " + error + " — scene changes cut instead of fading");
    }
    shown_ = live_.CurrentShared();
    shownScene_ = live_.Scene();
}

// The program on screen decides the parameters (its header may have changed), and its error
// the overlay's last line.
void LiveSession::UpdateProgram() {
    Guard("program: post", [&] { UpdatePost(); });
    // The scene's header alone unless a post chain adds inputs: no SceneInfo copy per frame.
    if (HasProgram() && postDecls_.empty()) FollowScene(state_, SceneOnScreen());
    else if (HasProgram()) FollowScene(state_, SceneWithPost());
    if (state_.sendFeedback && state_.pendingTargets.empty()) {
        input_.SendFeedback(state_.params, state_.currentPreset);
        state_.sendFeedback = false;
    }
    if (servers_ && servers_->Error() != shownError_) {   // said by Reload as it came
        shownError_ = servers_->Error();
    } else if (!servers_ && live_.Error() != shownError_) {
        shownError_ = live_.Error();
        state_.report.Say(shownError_.empty() ? "shader reloaded" : shownError_);
    }
    // The literal tier (LiveProgram::SetLiteralTier): said once per build on the terminal, and each
    // retune on the overlay's report too.
    const bool literalReady = live_.LiteralTierReady();
    if (literalReady && !literalReady_)
        std::fprintf(stderr, "sdfvj live: %s: a save that changes only numbers in its functions shows at once (literal tier)\n",
                     DisplayPath(live_.Key().scenePath).c_str());
    literalReady_ = literalReady;
    if (live_.LiteralSwaps() != literalSwaps_) {
        literalSwaps_ = live_.LiteralSwaps();
        state_.report.Say("shader retuned: the new numbers are on screen, its optimized program compiles behind them");
    }
    const bool evalReady = live_.EvaluatorTierReady();
    if (evalReady && !evalReady_)
        std::fprintf(stderr, "sdfvj live: %s: a save that edits its functions shows at once (evaluator tier)\n",
                     DisplayPath(live_.Key().scenePath).c_str());
    evalReady_ = evalReady;
    if (live_.EvaluatorSwaps() != evalSwaps_) {
        evalSwaps_ = live_.EvaluatorSwaps();
        state_.report.Say("shader edited: drawn by its evaluator at once, its optimized program compiles behind it");
    }
}

void LiveSession::LogParams(double now) {
    CopyParams(state_.params, &in_.params);
    if (!paramLog_) return;
    std::fprintf(paramLog_.get(), "%.4f", now);
    for (const auto& [name, value] : in_.params) std::fprintf(paramLog_.get(), " %s=%g", name.c_str(), value);
    std::fputc('\n', paramLog_.get());
}

// The scene's GPU time: the whole draw (scene, crossfade, upscale) inside one timer query of the
// ring; its result reaches the graph a few frames later (Poll never waits).
void LiveSession::Draw(double now) {
    const bool timed = !softwareGl_ && frameTimer_.Begin();
    const double t0 = Now();
    DrawScene(now);
    if (timed) frameTimer_.End();
    double budgetMs = 0;   // --frame-budget: GPU time, or on a software renderer the finished draw's wall time
    if (servers_)   // the render process's draw and hand-over (its wall time): this process only blits
        ui_.gpu.Add((float)(budgetMs = servers_->Servers().LastServerMs()));
    else if (!softwareGl_)
        for (const GpuTimerRing::Sample& s : frameTimer_.Poll()) ui_.gpu.Add((float)(budgetMs = s.ms));
    else if (budget_.desc.budgetMs > 0)
        glFinish(), budgetMs = 1000.0 * (Now() - t0);
    std::string say;
    if (budgetMs > 0 && LiveFrameBudgetStep(budget_, now, budgetMs, &in_.quality, &renderScale_, &say)) state_.report.Say(say);
}

// Each frame while "measure costs" runs: the program on screen once more, offscreen, with every
// effect on or one switched off (effect_costs.h). A new program makes the costs stale.
void LiveSession::MeasureEffectCosts() {
    if (!costs_.Started() || costs_.Done() || !HasProgram()) return;
    if (!(costs_.effects == KeyOnScreen().effects)) {
        costs_ = EffectCosts{};
        state_.report.Say("sdfvj live: effect costs: the program changed while measuring; press \"measure costs\" again");
        return;
    }
    int w = renderer_.Width(), h = renderer_.Height();
    if (servers_) {   // the server on screen draws each one offscreen and times it, in its process
        w = servers_->Servers().OnScreenLoad().width;
        h = servers_->Servers().OnScreenLoad().height;
        StepEffectCostsTimed(costs_, in_, [&](const FrameInputs& in) { return servers_->TimeDraw(in); },
                             softwareGl_ ? "timed in the render process on screen (glFinish + wall clock, software GL)"
                                         : "timed in the render process on screen (GPU timer queries)");
    } else {
        std::string error;
        if (!costRenderer_.Resize(w, h, &error)) return;
        StepEffectCosts(costs_, costRenderer_, *live_.Current(), live_.Scene(), in_);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    if (costs_.Done()) {
        std::string line = "effect costs at " + std::to_string(w) + "x" + std::to_string(h) + ":";
        for (size_t i = 0; i < costs_.rows.size(); ++i)
            line += (i ? ", " : " ") + costs_.rows[i].name + " " + EffectCostText(costs_.rows[i], costs_);
        state_.report.Say(line);
        std::fprintf(stderr, "  (%s)\n", EffectCostNote(costs_).c_str());
    }
}

void LiveSession::DrawScene(double now) {
    glfwGetFramebufferSize(window_, &fbw_, &fbh_);
    std::string error;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fbw_, fbh_);
    glClearColor(0.08f, 0.08f, 0.1f, 1.0f);   // until a first program compiles
    glClear(GL_COLOR_BUFFER_BIT);
    // The scene renders at renderScale_ of the window and is upscaled (linear) when it is smaller.
    const int rw = Scaled(fbw_), rh = Scaled(fbh_);
    if (state_.show.isfScene && fbw_ > 0 && fbh_ > 0) {   // an ISF generator: the chain draws it all
        in_.time = now;
        in_.frame = frame_++;
        DrawPost(0, rw, rh, now);
        return;
    }
    if (servers_ && fbw_ > 0 && fbh_ > 0) {
        in_.time = now;
        in_.frame = frame_++;
        DrawServerScene(now, rw, rh);
        return;
    }
    if (fbw_ > 0 && fbh_ > 0 && live_.Current()) {
        FrameHitch::Scope timed(&hitch_, "draw: scales ahead");
        DrawScalesAhead(now);
    }
    if (fbw_ <= 0 || fbh_ <= 0 || !live_.Current() || !renderer_.Resize(rw, rh, &error)) return;
    in_.time = now;
    in_.frame = frame_++;
    if (DrawFieldFade(now, rw, rh)) return;
    {
        FrameHitch::Scope timed(&hitch_, "draw: scene");
        renderer_.Draw(*live_.Current(), live_.Scene(), in_);
    }
    const double t = fade_.program ? (now - fade_.start) / fade_.seconds : 1.0;
    if (t < 1.0 && fadeRenderer_.Resize(rw, rh, &error)) {
        FrameInputs old = in_;
        old.params = fade_.params;
        FrameHitch::Scope timed(&hitch_, "draw: scene fading out");
        fadeRenderer_.Draw(*fade_.program, fade_.scene, old);
        timed.Done();
        const bool post = HasPost() && postInput_.Resize(rw, rh, &error);
        crossfade_.Draw(fadeRenderer_.Texture(), renderer_.Texture(), Ease(fade_.easing, t),
                        post ? postInput_.Framebuffer() : 0, post ? rw : fbw_, post ? rh : fbh_);
        if (post) DrawPost(postInput_.Texture(), rw, rh, now);
    } else {
        fade_ = Fade{};   // done: the old program may go
        PresentRenderer(rw, rh, now);
        return;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
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
    if (!o_.screenshot.empty() && o_.seconds > 0 && frame_ > 0 && Now() + 0.05 >= o_.seconds) SaveScreenshot(GL_BACK);
    glfwSwapBuffers(window_);
}

void LiveSession::Finish() {
    // Slow frames (software GL) or a closed window can end the show before Present() took the
    // screenshot: then the front buffer holds the last frame shown.
    if (!o_.screenshot.empty() && !shotWritten_ && frame_ > 0) SaveScreenshot(GL_FRONT);
    if (!o_.screenshot.empty() && frame_ == 0)
        std::fprintf(stderr, "sdfvj live: no frame of the scene was drawn, so no screenshot was written to %s\n",
                     o_.screenshot.c_str());
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

// --budget-floor only with a budget, and one that parses: a typo stops the launch with exit 2 (the
// show's own input, once it runs, never does; --seconds and --frame-budget are checked by the parser).
bool CheckBudgetFloor(const LiveOptions& o, std::string* error) {
    if (o.budgetFloor.empty()) return true;
    if (o.frameBudgetMs <= 0) {
        *error = "--budget-floor " + o.budgetFloor + " without --frame-budget MS, expected both (the floor bounds the budget's choices)";
        return false;
    }
    BudgetFloor floor;
    return ParseBudgetFloor(o.budgetFloor, &floor, error);
}

int RunLive(const LiveOptions& o) {
    std::string error;
    int w = 0, h = 0;
    LiveState state;
    if (!CheckBudgetFloor(o, &error) || !ParseSize(o.size, &w, &h, &error) || !OpenLiveState(o.show, o.mapping, &state, &error)) {
        std::fprintf(stderr, "sdfvj live: %s\n", error.c_str());
        return 2;
    }
    LiveWindow window;
    if (!window.Open(w, h, o.fullscreen, &error)) {
        std::fprintf(stderr, "sdfvj live: %s\n", error.c_str());
        return 2;
    }
    LiveSession session(o, std::move(state), window.Get());   // GL objects die before the window
    if (o.renderProcess) session.SetImporter(window.OpenImporter());
    session.SetPostContexts(window.PostContexts());
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
