// The pieces of `sdfvj live` that own the window, GL, devices and files: LiveWindow (the window,
// ImGui and the compile thread's context) and LiveSession (one show). cmd_live.cpp holds the frame,
// live_session_ui.cpp the keys and the overlay's glue. Render thread only. Internal to `sdfvj`.
#pragma once
#include <epoxy/gl.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>
#include <thread>

#include "app/commands.h"
#include "app/effect_costs.h"
#include "app/frame_budget.h"
#include "app/frame_hitch.h"
#include "app/live_overlay.h"
#include "app/live_forward.h"
#include "app/live_servers.h"
#include "app/live_session.h"
#include "app/live_sync.h"
#include "render/compile_worker.h"
#include "render/import_thread.h"
#include "render/field_morph.h"
#include "isf/isf.h"
#include "isf/isf_host.h"
#include "audio/audio.h"
#include "render/live_program.h"
#include "shader/watch.h"
#include "take/take.h"

namespace sdfvj {

// The window and its GL context, Dear ImGui on it, and the optional compile thread's hidden
// window. Created first and destroyed last: every GL object of the session dies before it.
class LiveWindow {
public:
    ~LiveWindow() {
        PendingProgram::SetWorker(nullptr);
        PendingProgram::SetLoader(nullptr);
        worker_.reset();   // no compile may outlive the windows
        importer_.reset();
        if (imgui_) {
            ImGui_ImplOpenGL3_Shutdown();
            ImGui_ImplGlfw_Shutdown();
            ImGui::DestroyContext();
        }
        if (importWindow_) glfwDestroyWindow(importWindow_);
        for (GLFWwindow* p : postWindows_)
            if (p) glfwDestroyWindow(p);
        if (compileWindow_) glfwDestroyWindow(compileWindow_);
        if (window_) glfwDestroyWindow(window_);
        if (glfw_) glfwTerminate();
    }
    bool Open(int w, int h, bool fullscreen, std::string* error) {
        // GLFW's own words on why it could not start (a display that refused us, none named).
        static std::string glfwError;
        glfwSetErrorCallback([](int, const char* what) { glfwError = what ? what : ""; });
        // A display that is named but does not answer at once (an X server still starting, or
        // refusing a connection for a moment under load) is asked again for 3 s before giving up.
        const char* display = std::getenv("DISPLAY");
        const bool named = (display && *display) || std::getenv("WAYLAND_DISPLAY");
        for (int attempt = 0; !(glfw_ = glfwInit()) && named && attempt < 6; ++attempt) {
            if (attempt == 0)
                std::fprintf(stderr, "sdfvj live: the display %s did not answer (%s); asking again for 3 s\n",
                             display ? display : "", glfwError.c_str());
            std::this_thread::sleep_for(std::chrono::milliseconds(500));
        }
        if (!glfw_) {
            *error = "no display (GLFW could not start: " + (glfwError.empty() ? std::string("no reason given") : glfwError) +
                     "); use `sdfvj render` for headless output";
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
        // A tap shorter than a frame still counts: glfwGetKey says PRESS once after it (a slow
        // frame would otherwise see press and release in one poll and miss Esc, F11 or a preset).
        glfwSetInputMode(window_, GLFW_STICKY_KEYS, GLFW_TRUE);
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
        // Where the compile process hands over binaries (NVIDIA), the same hidden window's thread
        // is the loader: it loads each binary and uses it once, so the driver's finishing of a
        // loaded program at its first use (150-600 ms) never lands in a frame (issue 12); on
        // llvmpipe it loads the program cache's binaries and draws each once, so its JIT code is in
        // Mesa's disk cache before the show's first draw (LiveProgram::LoaderDefault).
        const bool loader = LiveProgram::LoaderDefault();
        if (PreferCompileThread() || loader) {
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
            if (worker_->Ok() && PreferCompileThread()) PendingProgram::SetWorker(worker_.get());
            if (worker_->Ok() && loader) PendingProgram::SetLoader(worker_.get());
            if (!worker_->Ok()) std::fprintf(stderr, "sdfvj live: no compile thread; shaders compile on the render thread\n");
        }
        return true;
    }
    GLFWwindow* Get() const { return window_; }
    // `live --render-process`: the thread that imports each new render server's frame images, with a
    // hidden window's context that shares objects with this one (render/import_thread.h). Null
    // where it cannot be made: the render thread imports them.
    ImportThread* OpenImporter() {
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        importWindow_ = glfwCreateWindow(1, 1, "sdfvj importer", nullptr, window_);
        glfwWindowHint(GLFW_VISIBLE, GLFW_TRUE);
        if (!importWindow_) return nullptr;
        GLFWwindow* iw = importWindow_;
        importer_ = std::make_unique<ImportThread>(
            [iw] {
                glfwMakeContextCurrent(iw);
                return glfwGetCurrentContext() == iw;
            },
            [] { glfwMakeContextCurrent(nullptr); });
        if (!importer_->Ok()) importer_.reset();
        return importer_.get();
    }
    // The post chain's two contexts (isf/isf_host.h), each a hidden window's that shares objects
    // with this one; opened at the first post chain. Empty where they cannot be made: the chain
    // builds and draws in the window's context.
    std::function<std::array<IsfHostContext, 2>()> PostContexts() {
        return [this] {
            std::array<IsfHostContext, 2> out;
            glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
            for (GLFWwindow*& p : postWindows_)
                if (!p) p = glfwCreateWindow(1, 1, "sdfvj post", nullptr, window_);
            glfwWindowHint(GLFW_VISIBLE, GLFW_TRUE);
            if (!postWindows_[0] || !postWindows_[1]) return out;
            for (size_t i = 0; i < 2; ++i) {
                GLFWwindow* p = postWindows_[i];
                out[i] = {[p] {
                              glfwMakeContextCurrent(p);
                              return glfwGetCurrentContext() == p;
                          },
                          [] { glfwMakeContextCurrent(nullptr); }};
            }
            return out;
        };
    }
private:
    bool glfw_ = false, imgui_ = false;
    GLFWwindow* window_ = nullptr;
    std::array<GLFWwindow*, 2> postWindows_{};
    GLFWwindow* compileWindow_ = nullptr;
    GLFWwindow* importWindow_ = nullptr;
    std::unique_ptr<CompileWorker> worker_;
    std::unique_ptr<ImportThread> importer_;
};

// One show: owns what it runs on; Frame() is the frame loop's body (cmd_live.cpp).
class LiveSession {
public:
    LiveSession(const LiveOptions& o, LiveState state, GLFWwindow* window)
        : o_(o), state_(std::move(state)), window_(window), start_(std::chrono::steady_clock::now()),
          input_(InputConfig(o), queue_, [this] { return Now(); }) {}

    // Everything that may fail with a message before the first frame. False: exit code 2.
    bool Start(std::string* error);
    // --render-process: the thread that imports each new server's images (LiveWindow::OpenImporter).
    // Before Start; it outlives the session.
    void SetImporter(ImportThread* importer) { importer_ = importer; }
    // The post chain's own contexts, opened when a chain is first asked for (LiveWindow::PostContexts).
    void SetPostContexts(std::function<std::array<IsfHostContext, 2>()> open) { postContexts_ = std::move(open); }
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
    void DrawScene(double now);
    void MeasureEffectCosts();
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
        FrameHitch::Scope timed(&hitch_, name);   // the stage's time to --hitch-ms, however it ends
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
    FrameHitch hitch_{o_.hitchMs};   // --hitch-ms: a long frame said, with where its time went
    EventQueue queue_;
    InputSession input_;
    FolderWatcher watcher_;
    std::vector<std::string> watched_;   // canonical folders
    LiveProgram live_;
    FrameRenderer renderer_;
    // --render-process: the scene drawn by render servers (live_servers.h); null: drawn here by live_.
    std::unique_ptr<LiveServers> servers_;
    ImportThread* importer_ = nullptr;
    GLuint serverFbo_ = 0;   // reads the server's frame for the blit to the window
    void StartServers();
    void DrawServerScene(double now, int rw, int rh);
    void PresentServerTexture(unsigned texture, int w, int h, double now, unsigned readFbo = 0);
    // live_morph.cpp, --render-process: the field morph drawn by a server held for it.
    void PrepareServerMorph();
    bool ServerFadeMorphsFields();
    bool DrawServerFieldFade(double now);
    VariantKey serverMorphFor_;   // the variant the last PrepareServerMorph was asked for
    void FadeServersIfSceneChanged(double now);
    // The program on screen, wherever it is drawn: its scene, its variant, whether there is one.
    const SceneInfo& SceneOnScreen() const { return servers_ ? servers_->Scene() : live_.Scene(); }
    const VariantKey& KeyOnScreen() const { return servers_ ? servers_->Key() : live_.Key(); }
    bool HasProgram() const { return servers_ ? servers_->OnScreen() : live_.Current() != nullptr; }
    // A side of the scene's render size for a window side of n pixels: renderScale_ of it, at least 1.
    int Scaled(int n) const { return std::max(1, (int)std::lround(n * renderScale_)); }
    // A scene change with a morph time fades from the old scene's frame to the new one's; the old
    // program stays alive (shared) and keeps rendering with its last values until the fade ends.
    struct Fade {
        std::shared_ptr<const Program> program;
        SceneInfo scene;
        std::vector<std::pair<std::string, float>> params;
        double start = 0.0, seconds = 0.0;
        Easing easing = Easing::Smooth;
        bool field = false;     // the fields morph in one program (live_morph.cpp), not the frames
        bool waiting = false;   // the morph program still compiles: the old scene holds, t stays 0
        bool server = false;    // --render-process: from the frames of the server of the scene before
    } fade_;
    FieldMorph fieldMorph_;
    // Audio through JACK (--audio): its features enter the queue each frame like a knob.
    std::unique_ptr<AudioInput> audio_;
    // The ISF post chain (live_post.cpp) and its inputs, which join the scene's parameters. It is
    // built, and drawn, in contexts of its own (isf/isf_host.h), so a save holds no frame.
    std::unique_ptr<IsfHost> post_;
    std::function<std::array<IsfHostContext, 2>()> postContexts_;
    std::string postShown_, postSay_;
    bool HasPost() const { return post_ && !post_->Chain().Empty(); }
    // This process's chain draws over the frame: it has one, and the server on screen drew none.
    bool ShowDrawsPost() const { return HasPost() && !(servers_ && servers_->PostOnScreen()); }
    // --render-process: the post chain is drawn by the render servers over each frame (LiveServers::
    // SetPost), so its builds, first draws and new targets land in their processes; this process
    // only reads the files' headers. SDFVJ_POST_IN_SERVER=0: in this process, as before session 34.
    bool postInServers_ = false;
    bool postHere_ = true;   // the chain asked for is this process's (PostInServers false)
    bool PostInServers(const std::vector<IsfFile>& files) const;
    // The chain's files resolved and parsed (no GL); false with the file:line of the first that is not.
    bool LoadPostFiles(const std::string& list, std::vector<IsfFile>* files, std::string* error) const;
    void SetPostDecls(const std::vector<IsfFile>& files);
    void SetServersPost(const std::vector<IsfFile>& files);   // LiveServers::SetPost of their paths
    std::vector<ParamDecl> postDecls_;
    FrameRenderer postInput_;   // a crossfade's mix, when a post chain filters it
    double postLast_ = 0.0;
    void UpdatePost();
    SceneInfo SceneWithPost() const;
    void ReloadPost(const std::vector<std::string>& changed);
    bool DrawPost(unsigned texture, int w, int h, double now);
    void PresentRenderer(int rw, int rh, double now);   // renderer_'s frame to the window, through the post chain
    void PrepareFieldMorph();
    // live_prefetch.cpp: the variants the effect pads and presets reach, built ahead (LiveProgram::Prefetch).
    void PrefetchReachable(double now);
    VariantKey prefetchFor_;
    double prefetchQuietSince_ = 0.0;
    bool prefetchQueued_ = false;
    bool FadeMorphsFields();
    bool DrawFieldFade(double now, int rw, int rh);
    std::shared_ptr<const Program> shown_;   // the program the last frame showed, and its scene
    SceneInfo shownScene_;
    FrameRenderer fadeRenderer_;
    Crossfade crossfade_;
    // GPU ms of the scene draw for the overlay's graph: timer queries read when they are ready,
    // never waited for; off on a software renderer, whose timer queries mean nothing.
    GpuTimerRing frameTimer_;
    bool softwareGl_ = false;
    // "measure costs": one extra offscreen draw a frame until each effect's cost is known.
    EffectCosts costs_;
    FrameRenderer costRenderer_;
    void StartFadeIfSceneChanged(double now);
    FrameInputs in_;
    LiveSync sync_;              // --sync: the show clock from a master (live_sync.h)
    LiveForward forward_;        // --forward: follower nodes (live_forward.h)
    double takeAt_ = 0.0;        // where the rehearsal take's cursor is, on the show clock (--sync mtc)
    double SyncShowClock(std::vector<ControlEvent>* events, double wall);
    TakeRecorder recorder_;
    Take rehearsal_;
    std::unique_ptr<ReplayCursor> replay_;
    std::unique_ptr<FILE, int (*)(FILE*)> paramLog_{nullptr, &std::fclose};
    std::string shownError_;
    bool literalReady_ = false;   // the literal tier's readiness and retunes, as last reported
    int literalSwaps_ = 0;
    bool evalReady_ = false;      // the evaluator tier's readiness and saves drawn by it, as last reported
    int evalSwaps_ = 0;
    bool overlay_ = true, tabWasDown_ = false, shotWritten_ = false, shotWaitSaid_ = false;
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
    FrameBudget budget_;         // --frame-budget: moves renderScale_ and in_.quality
    // The render scales its moves reach, drawn once ahead at each window size (DrawScalesAhead).
    bool scalesAheadOn_ = false;
    int aheadW_ = 0, aheadH_ = 0;           // the window size they were drawn at
    int pendingW_ = 0, pendingH_ = 0;       // a new window size, and since when it has held
    double pendingSince_ = 0.0;
    void DrawScalesAhead(double now);
    float renderScale_ = 1.0f;   // --render-scale and the overlay's resolution slider
    // Other sizes' render targets kept (FrameRenderer::SetKeptSizes, IsfHost::SetKeptSizes), so a scale
    // change back to a size drawn at before allocates nothing: SDFVJ_KEEP_SIZES=N, default 4.
    int keepSizes_ = 4;
    uint64_t internalErrors_ = 0;
};

}  // namespace sdfvj
