// `sdfvj live`: a GLFW window, MIDI and OSC in, the performer's overlay on top.
//
// The frame loop reads top to bottom: clock -> drain events -> mapping -> smoothing -> draw ->
// overlay -> swap. Input threads (RtMidi, liblo, replay) only push onto the queue; all GL and all
// parameter state live on this thread.
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
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>

#include "app/commands.h"
#include "app/live_support.h"
#include "render/compile_worker.h"
#include "render/live_program.h"
#include "shader/watch.h"
#include "take/take.h"

namespace sdfvj {

namespace fs = std::filesystem;

namespace {

// Tap tempo: the beat the performer taps on a pad drives u_beat (phase 0..1 per beat).
struct TapTempo {
    double bpm = 120.0;
    double origin = 0.0;            // time of a beat
    std::vector<double> taps;
    void Tap(double now) {
        if (!taps.empty() && now - taps.back() > 2.0) taps.clear();   // a pause starts a new count
        taps.push_back(now);
        if (taps.size() > 5) taps.erase(taps.begin());
        if (taps.size() >= 2) {
            std::vector<double> gaps;
            for (size_t i = 1; i < taps.size(); ++i) gaps.push_back(taps[i] - taps[i - 1]);
            std::sort(gaps.begin(), gaps.end());
            double gap = gaps[gaps.size() / 2];
            if (gap > 0.2 && gap < 2.0) bpm = 60.0 / gap;
        }
        origin = now;
    }
    float Phase(double now) const {
        double beats = (now - origin) * bpm / 60.0;
        return (float)(beats - std::floor(beats));
    }
};

// Resolves a preset request from a pad or OSC: a name, a file name, an index into
// `sdfvj list`'s presets, or next/prev.
std::string ResolvePresetRequest(const std::string& request, const std::string& current) {
    const std::vector<std::string> presets = ListPresets();
    if (presets.empty()) return "";
    int at = 0;
    for (size_t i = 0; i < presets.size(); ++i)
        if (presets[i] == current) at = (int)i;
    if (request == "next") return presets[(size_t)(at + 1) % presets.size()];
    if (request == "prev") return presets[(size_t)(at + (int)presets.size() - 1) % presets.size()];
    if (!request.empty() && std::all_of(request.begin(), request.end(), ::isdigit)) {
        size_t i = std::stoul(request);
        return i < presets.size() ? presets[i] : "";
    }
    for (const auto& p : presets)
        if (p == request || p == request + ".json") return p;
    return "";
}

struct WindowCloser { void operator()(GLFWwindow* w) const { glfwDestroyWindow(w); glfwTerminate(); } };

// The overlay: what the performer needs, nothing the audience should see (Tab hides it).
void DrawOverlay(const Show& show, ParamState& params, const InputSession& input, const std::string& error,
                 double fps, size_t recorded, bool recording) {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.6f);
    ImGui::Begin("sdfvj", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("%s  [%s, %s]  %.1f fps", show.scene.name.c_str(), DescribeEffects(show.effects).c_str(),
                RenderPathName(show.path), fps);
    for (size_t i = 0; i < params.decls.size(); ++i) {
        const ParamDecl& d = params.decls[i];
        float v = params.target[i];
        if (ImGui::SliderFloat(d.label.c_str(), &v, d.minValue, d.maxValue)) SetParamTarget(params, (int)i, v);
    }
    for (const std::string& line : input.StatusLines()) ImGui::TextDisabled("%s", line.c_str());
    if (recording) ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "REC  %zu events", recorded);
    if (!error.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", error.c_str());
    ImGui::TextDisabled("Tab: hide overlay   Esc: quit");
    ImGui::End();
}

}  // namespace

int RunLive(const LiveOptions& o) {
    std::string error;
    int w = 0, h = 0;
    if (!ParseSize(o.size, &w, &h, &error)) { std::fprintf(stderr, "sdfvj live: %s\n", error.c_str()); return 2; }
    Show show;
    if (!PrepareShow(o.show, &show, &error)) { std::fprintf(stderr, "sdfvj live: %s\n", error.c_str()); return 2; }
    Mapping mapping;
    if (!LoadShowMapping(show, o.mapping, &mapping, &error)) { std::fprintf(stderr, "%s\n", error.c_str()); return 2; }
    // --log-params FILE appends one line per frame, "time name=value ...", with the values the
    // frame renders (after mapping and smoothing): for tests and for debugging a mapping. Line
    // buffered, so a reader sees each frame as soon as it is drawn.
    std::unique_ptr<FILE, int (*)(FILE*)> paramLog(nullptr, &std::fclose);
    if (!o.logParams.empty()) {
        paramLog.reset(std::fopen(o.logParams.c_str(), "a"));
        if (!paramLog) {
            std::fprintf(stderr, "sdfvj live: cannot write --log-params %s: %s\n", o.logParams.c_str(), std::strerror(errno));
            return 2;
        }
        std::setvbuf(paramLog.get(), nullptr, _IOLBF, 0);
    }

    if (!glfwInit()) {
        std::fprintf(stderr, "sdfvj live: no display (GLFW could not start); use `sdfvj render` for headless output\n");
        return 2;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWmonitor* monitor = o.fullscreen ? glfwGetPrimaryMonitor() : nullptr;
    std::unique_ptr<GLFWwindow, WindowCloser> window(glfwCreateWindow(w, h, "sdfvj", monitor, nullptr));
    if (!window) {
        glfwTerminate();
        std::fprintf(stderr, "sdfvj live: cannot open an OpenGL 4.5 core window on this display\n");
        return 2;
    }
    glfwMakeContextCurrent(window.get());
    glfwSwapInterval(1);
    std::fprintf(stderr, "GL: %s, %s\n", (const char*)glGetString(GL_RENDERER), (const char*)glGetString(GL_VERSION));

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui_ImplGlfw_InitForOpenGL(window.get(), true);
    ImGui_ImplOpenGL3_Init("#version 450");

    int rc = 0;
    {   // GL objects live in this scope, so they go before the context does.
        if (o.show.path == "auto") {
            std::string log;
            show.path = ProbeRenderPath(show.scene, &log);
            std::fprintf(stderr, "%s\n", log.c_str());
        } else {
            show.path = o.show.path == "compute" ? RenderPath::Compute : RenderPath::Fragment;
        }
        // Where it helps (Mesa; see PreferCompileThread), shader compiles run on a worker thread
        // with a hidden window's context that shares programs with this one, so a reload or a
        // variant switch does not stall frames. Elsewhere the driver's parallel compile is used.
        GLFWwindow* compileWindow = nullptr;
        if (PreferCompileThread()) {
            glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
            compileWindow = glfwCreateWindow(1, 1, "sdfvj compiler", nullptr, window.get());
            glfwWindowHint(GLFW_VISIBLE, GLFW_TRUE);
        }
        std::unique_ptr<CompileWorker> worker;
        if (compileWindow) {
            worker = std::make_unique<CompileWorker>([compileWindow] {
                glfwMakeContextCurrent(compileWindow);
                return glfwGetCurrentContext() == compileWindow;
            });
            if (worker->Ok()) PendingProgram::SetWorker(worker.get());
            else std::fprintf(stderr, "sdfvj live: no compile thread; shaders compile on the render thread\n");
        }
        struct WorkerStop {   // runs first at scope exit: no compile may outlive the windows
            std::unique_ptr<CompileWorker>& w;
            GLFWwindow* win;
            ~WorkerStop() { PendingProgram::SetWorker(nullptr); w.reset(); if (win) glfwDestroyWindow(win); }
        } workerStop{worker, compileWindow};
        // Hot reload: shaders, mappings and presets are watched as folders, and so are the folders
        // of the mapping and the preset on stage when they live elsewhere (--mapping/--preset FILE).
        // Files are told apart by their canonical paths; messages name them as given.
        const std::string mappingFile = ResolveMappingPath(show, o.mapping);
        const std::string mappingPath = fs::weakly_canonical(mappingFile).string();
        std::string presetFile = show.preset.path;   // the preset on stage ("" = none) ...
        std::string presetPath = presetFile.empty() ? "" : fs::weakly_canonical(presetFile).string();   // ... canonical
        FolderWatcher watcher;
        std::vector<std::string> watched;            // canonical folders
        auto watchFolder = [&](const std::string& dir) {
            const std::string canonical = fs::weakly_canonical(dir).string();
            if (std::find(watched.begin(), watched.end(), canonical) != watched.end()) return;
            if (watcher.Watch(canonical, &error)) watched.push_back(canonical);
            else std::fprintf(stderr, "sdfvj live: %s\n", error.c_str());
        };
        for (const char* dir : {"shaders/lib", "shaders/scenes", "shaders/render", "mappings", "presets"})
            watchFolder(DataRoot() + "/" + dir);
        watchFolder(fs::path(mappingPath).parent_path().string());
        if (!presetPath.empty()) watchFolder(fs::path(presetPath).parent_path().string());
        LiveProgram live;
        live.Request(VariantKey{show.scene.path, show.effects, show.path});
        live.Wait();
        if (!live.Current()) {
            std::fprintf(stderr, "%s\n", live.Error().c_str());
            rc = 1;
        }
        std::string shownError;
        const auto start = std::chrono::steady_clock::now();
        auto clock = [start] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
        EventQueue queue;
        InputOptions io;
        io.midiPort = o.midi;
        io.oscPort = o.oscPort;
        io.oscFeedback = o.oscFeedback;
        InputSession input(io, queue, clock);
        for (const auto& line : input.StatusLines()) std::fprintf(stderr, "%s\n", line.c_str());

        TakeRecorder recorder;
        if (!o.record.empty() && !recorder.Open(o.record, &error))
            std::fprintf(stderr, "sdfvj live: not recording: %s\n", error.c_str());
        Take rehearsal;
        std::unique_ptr<ReplayCursor> replay;
        if (!o.replay.empty()) {
            TakeReadResult r = ReadTake(o.replay, &rehearsal);
            if (!r.ok) std::fprintf(stderr, "sdfvj live: not replaying: %s\n", r.error.c_str());
            else replay = std::make_unique<ReplayCursor>(rehearsal);
        }

        ParamState params = ShowParamState(show);
        MappingState mstate;
        MappingActions actions;
        TapTempo tempo;
        std::string currentPreset = fs::path(show.preset.path).filename().string();   // for next/prev
        double lastMessageTime = -1.0;
        size_t suppressedMessages = 0;
        std::vector<std::string> presetReloads;   // the preset on stage was saved: apply it again next frame
        FrameRenderer fr;
        FrameInputs in;
        in.quality = show.quality;
        bool overlay = !o.hideOverlay;   // --hide-overlay: start as after Tab (clean screenshots)
        bool tabWasDown = false;
        double last = clock(), fps = 0;
        int frame = 0;
        bool shotWritten = false;
        auto saveScreenshot = [&](GLenum buffer, int fbw, int fbh) {
            std::vector<uint8_t> rgba((size_t)fbw * fbh * 4);
            glReadBuffer(buffer);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glReadPixels(0, 0, fbw, fbh, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
            std::vector<uint8_t> flipped(rgba.size());
            for (int y = 0; y < fbh; ++y)
                std::copy_n(&rgba[(size_t)(fbh - 1 - y) * fbw * 4], (size_t)fbw * 4, &flipped[(size_t)y * fbw * 4]);
            std::string err;
            if (!WritePng(o.screenshot, fbw, fbh, flipped, &err)) std::fprintf(stderr, "sdfvj live: %s\n", err.c_str());
            return true;
        };
        while (rc == 0 && !glfwWindowShouldClose(window.get())) {
            glfwPollEvents();
            const double now = clock();
            const double dt = now - last;
            last = now;
            if (frame >= 2) fps = fps == 0 ? 1.0 / std::max(dt, 1e-6) : 0.95 * fps + 0.05 / std::max(dt, 1e-6);  // first frames include start-up
            if (o.seconds > 0 && now >= o.seconds) break;
            if (glfwGetKey(window.get(), GLFW_KEY_ESCAPE) == GLFW_PRESS) break;
            const bool tabDown = glfwGetKey(window.get(), GLFW_KEY_TAB) == GLFW_PRESS;
            if (tabDown && !tabWasDown) overlay = !overlay;
            tabWasDown = tabDown;

            // Rehearsal: the take plays through the same queue a controller feeds.
            if (replay)
                for (ControlEvent& e : replay->Until(now)) queue.Push(std::move(e));
            actions.Clear();
            std::vector<std::string> reloadsNow;
            reloadsNow.swap(presetReloads);
            for (const ControlEvent& e : queue.DrainUntil(now)) {
                if (recorder.IsOpen()) recorder.Record(e);
                ApplyEvent(mapping, mstate, e, params, &actions);
            }
            // Bad-input reports: at most one line a second, so a flood cannot stall the frame.
            if (!actions.messages.empty()) {
                if (now - lastMessageTime >= 1.0) {
                    std::fprintf(stderr, "%s", actions.messages.back().c_str());
                    if (suppressedMessages + actions.messages.size() > 1)
                        std::fprintf(stderr, " (and %zu more in the last second)", suppressedMessages + actions.messages.size() - 1);
                    std::fputc('\n', stderr);
                    lastMessageTime = now;
                    suppressedMessages = 0;
                } else {
                    suppressedMessages += actions.messages.size();
                }
            }
            if (actions.tapTempo) tempo.Tap(now);
            // Preset pads and /sdfvj/preset: values glide there through smoothing; a new scene or
            // effect set compiles while the current one keeps rendering. A saved preset on stage is
            // applied the same way; when it does not load, the current values stay.
            auto applyPreset = [&](const std::string& request, const std::string& file, bool reload) {
                ShowOptions so = o.show;
                so.scene.clear();
                so.params.clear();
                so.preset = file;
                Show next;
                std::string err;
                if (file.empty() || !PrepareShow(so, &next, &err)) {
                    if (reload) std::fprintf(stderr, "%s — keeping the current values\n", err.c_str());
                    else std::fprintf(stderr, "sdfvj live: preset '%s': %s\n", request.c_str(), file.empty() ? "no such preset" : err.c_str());
                    return;
                }
                next.path = show.path;
                const bool sameScene = next.scene.path == show.scene.path;
                show = std::move(next);
                presetFile = show.preset.path;
                presetPath = fs::weakly_canonical(presetFile).string();
                currentPreset = fs::path(presetFile).filename().string();
                watchFolder(fs::path(presetPath).parent_path().string());
                if (!sameScene) params = ShowParamState(show);
                for (const auto& [pname, value] : show.params) {
                    int i = FindParam(params, pname);
                    if (i >= 0) SetParamTarget(params, i, value);
                }
                live.Request(VariantKey{show.scene.path, show.effects, show.path});
                input.SendFeedback(params, currentPreset);
                if (reload) std::fprintf(stderr, "reloaded %s (%s)\n", presetFile.c_str(), show.scene.name.c_str());
                else std::fprintf(stderr, "preset %s (%s)\n", currentPreset.c_str(), show.scene.name.c_str());
            };
            for (const std::string& file : reloadsNow) applyPreset(file, file, true);
            for (const std::string& request : actions.presetSelect) {
                const std::string name = ResolvePresetRequest(request, currentPreset);
                applyPreset(request, name.empty() ? "" : (fs::path(DataRoot()) / "presets" / name).string(), false);
            }
            // Effect pads and /sdfvj/effect/<name>: a new variant compiles while the old one renders.
            if (!actions.effectToggles.empty()) {
                EffectSet e = live.Key().effects;
                for (const auto& [name, on] : actions.effectToggles) {
                    std::string err;
                    if (!ParseEffectList((on ? "" : "-") + name, &e, &err)) std::fprintf(stderr, "%s\n", err.c_str());
                }
                VariantKey key = live.Key();
                key.effects = e;
                live.Request(key);
                show.effects = e;
            }
            StepSmoothing(params, dt);
            CopyParams(params, &in.params);
            if (paramLog) {
                std::fprintf(paramLog.get(), "%.4f", now);
                for (const auto& [name, value] : in.params) std::fprintf(paramLog.get(), " %s=%g", name.c_str(), value);
                std::fputc('\n', paramLog.get());
            }

            // Hot reload: shader files through LiveProgram, the mapping here (last good kept).
            const std::vector<std::string> changed = watcher.Poll();
            live.Update(changed);
            for (const std::string& f : changed) {
                const std::string path = fs::weakly_canonical(f).string();
                // The preset on stage was edited: apply it again next frame (a broken save is
                // reported and the current values stay).
                if (!presetPath.empty() && path == presetPath &&
                    std::find(presetReloads.begin(), presetReloads.end(), presetFile) == presetReloads.end())
                    presetReloads.push_back(presetFile);
                if (path != mappingPath) continue;
                Mapping next;
                LoadResult r = LoadMapping(mappingFile, &next);
                if (!r.ok) {
                    std::fprintf(stderr, "%s — keeping the previous mapping\n", r.error.c_str());
                    continue;
                }
                std::string problems;
                if (!ValidateMapping(next, params.decls, &problems))
                    std::fprintf(stderr, "%s (entries for other scenes are ignored)\n", problems.c_str());
                mapping = std::move(next);
                mstate = MappingState{};
                std::fprintf(stderr, "reloaded %s\n", mappingFile.c_str());
            }
            if (live.Error() != shownError) {
                shownError = live.Error();
                if (!shownError.empty()) std::fprintf(stderr, "%s\n", shownError.c_str());
                else std::fprintf(stderr, "shader reloaded\n");
            }
            error = shownError;
            if (live.Scene().params.size() != params.decls.size()) params = ShowParamState(show);

            int fbw = 0, fbh = 0;
            glfwGetFramebufferSize(window.get(), &fbw, &fbh);
            if (fbw > 0 && fbh > 0 && fr.Resize(fbw, fbh, &error)) {
                in.time = now;
                in.frame = frame++;
                in.beat = tempo.Phase(now);
                if (live.Current()) fr.Draw(*live.Current(), live.Scene(), in);
                glBindFramebuffer(GL_READ_FRAMEBUFFER, fr.Framebuffer());
                glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
                glBlitFramebuffer(0, 0, fbw, fbh, 0, 0, fbw, fbh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
                glBindFramebuffer(GL_FRAMEBUFFER, 0);
            }
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
            if (overlay) DrawOverlay(show, params, input, error, fps, recorder.Recorded(), recorder.IsOpen());
            ImGui::Render();
            glViewport(0, 0, fbw, fbh);
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            if (!o.screenshot.empty() && o.seconds > 0 && clock() + 0.05 >= o.seconds)
                shotWritten = saveScreenshot(GL_BACK, fbw, fbh);
            glfwSwapBuffers(window.get());
        }
        // Slow frames (software GL) or a closed window can end the loop before the check above
        // fired: then the front buffer holds the last frame shown.
        if (!o.screenshot.empty() && !shotWritten && frame > 0) {
            int fbw = 0, fbh = 0;
            glfwGetFramebufferSize(window.get(), &fbw, &fbh);
            if (fbw > 0 && fbh > 0) saveScreenshot(GL_FRONT, fbw, fbh);
        }
        if (recorder.IsOpen()) {
            recorder.Close(clock());
            std::fprintf(stderr, "recorded %zu events to %s\n", recorder.Recorded(), o.record.c_str());
        }
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    return rc;
}

}  // namespace sdfvj
