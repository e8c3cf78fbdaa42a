// StageRun: `sdfvj bench reload --modes stage` (issue 12, session 14: a lever measured before it
// is built into `live`). NVIDIA finishes a program at its first use on a context, on the thread
// that uses it (a use by another thread, even on the same context, did not carry over: adopt-
// process), and that first use stalls whatever thread makes it for 120-700 ms.
//
// Here each program gets a stage: a thread of its own with a context that shares objects with
// the render context. The compile process builds the program; the new stage's thread loads the
// binary, uses it once, makes its own FrameRenderer and draws one frame, all while the render
// thread goes on drawing through the stage on screen. Then the new stage goes on screen: every
// frame the render thread asks the stage on screen to draw (its thread, its context, the program
// it finished), waits for its fence on the GPU (glWaitSync) and blits the shared texture into the
// target it presents, as `live` would on its window. The old stage's thread ends. Without a
// compile process (a driver with no binaries) the new stage's thread compiles the program itself.
// Render thread only; each stage's GL calls run on that stage's thread.
#pragma once
#include <epoxy/gl.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "app/bench_adopt.h"
#include "render/compile_process.h"
#include "render/render.h"

namespace sdfvj {

// A thread with a context current on it, running the tasks given to it in order.
class GlThread {
public:
    explicit GlThread(HeadlessContext* context);
    ~GlThread();   // runs what is queued, releases the context, joins
    GlThread(const GlThread&) = delete;
    GlThread& operator=(const GlThread&) = delete;
    void Post(std::function<void()> task);
    // Runs `task` there and waits for it.
    void Run(std::function<void()> task);
    bool Ok() const { return ok_; }

private:
    void Loop(HeadlessContext* context);
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::deque<std::function<void()>> tasks_;
    uint64_t posted_ = 0, finished_ = 0;
    bool quit_ = false, ok_ = true;
    std::thread thread_;
};

class StageRun : public HandOverRun {
public:
    explicit StageRun(CompileProcess* process) : process_(process) {}
    ~StageRun();
    StageRun(const StageRun&) = delete;
    StageRun& operator=(const StageRun&) = delete;
    // The first program, compiled and drawn on the first stage; `gl` (the render context,
    // current) holds the target frames are presented into.
    bool Start(HeadlessContext& gl, const std::string& scenePath, RenderPath path, int width, int height, std::string* error) override;
    // The reload step: a save goes to the compile process; its binary to a new stage; a stage
    // that has drawn its first frame goes on screen. True when the program on screen changed.
    bool Update(const std::vector<std::string>& changed, const std::string& scenePath, RenderPath path, std::string* error) override;
    // One frame: drawn by the stage on screen, presented on the render context.
    void Draw(const FrameInputs& in) override;
    double LastBuildMs() const override { return lastStageMs_; }
    std::string Details() const override;

    // A program with the thread and context that finished it, and its renderer there.
    struct Stage {
        HeadlessContext context;
        std::unique_ptr<GlThread> thread;
        std::unique_ptr<Program> program;
        std::unique_ptr<FrameRenderer> renderer;
        SceneInfo scene;
        std::atomic<bool> ready{false};
        std::string error;   // set on the stage's thread before `ready`
        double ms = 0;
        double useMs = 0, firstFrameMs = 0;   // its load (or compile) + first use; its first real frame
    };

private:
    bool NewStage(std::unique_ptr<Stage>* out, std::string* error);
    // A new stage that loads (format, binary), or compiles pendingSrc_ when binary is empty, uses
    // the program once and draws its first frame, on its own thread.
    bool StartStage(unsigned format, std::vector<uint8_t> binary, RenderPath path, std::string* error);

    CompileProcess* process_ = nullptr;
    uint64_t ticket_ = 0;
    HeadlessContext* main_ = nullptr;
    std::unique_ptr<Stage> onScreen_, next_;
    std::vector<std::unique_ptr<Stage>> retired_;   // ended on the way out (a context is destroyed on the render thread)
    ShaderSource pendingSrc_;
    SceneInfo pendingScene_;
    FrameInputs lastInputs_;
    std::unique_ptr<PresentTarget> present_;   // on main_
    int w_ = 0, h_ = 0;
    double lastStageMs_ = 0;
    std::vector<std::pair<double, double>> stageTimes_;
};

}  // namespace sdfvj
