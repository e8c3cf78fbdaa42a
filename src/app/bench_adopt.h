// AdoptRun: `sdfvj bench reload --modes adopt|adopt-process` (issue 12's lever, measured here
// first): each program is drawn on the context that finished it.
//
// Each save gets a new context that shares objects with the render context; a CompileWorker on it
// compiles, links and uses the program once (PrimeProgram), then ends, leaving the context free;
// from then on the render thread draws the scene with that context current, into a texture of the
// share group, and presents it on its own context (a fence, then a blit), as `live` would present
// on its window. A driver that finishes a program once per context (NVIDIA at first use, llvmpipe's
// JIT with its disk cache off) has then already finished it where it is drawn. adopt-process: the
// compile process compiles (no driver lock of ours is held: NVIDIA serializes compiles
// process-wide) and the new context's thread loads its binary and uses it once; then the same
// hand-over. Render thread only.
#pragma once
#include <epoxy/gl.h>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "render/compile_process.h"
#include "render/compile_worker.h"
#include "render/render.h"

namespace sdfvj {

// The target a bench presents into on the render context, as `live` presents on its window: a
// texture of another context of the share group is blitted into it (after the caller's fence).
class PresentTarget {
public:
    ~PresentTarget();   // the render context must be current
    void Create(int width, int height);
    void Blit(unsigned sharedTexture);
    // The same through readFbo, a framebuffer of this context that already reads it; attachMs: what
    // getting it took (the caller's, reported as LastAttachMs).
    void Blit(unsigned sharedTexture, unsigned readFbo, double attachMs);
    // The last Blit's attach of a texture it had not read the frame before (glFramebufferTexture2D
    // and glCheckFramebufferStatus, on the CPU), 0 when it read the same one again.
    double LastAttachMs() const { return attachMs_; }
private:
    GLuint tex_ = 0, fbo_ = 0, readFbo_ = 0, readTex_ = 0;
    double attachMs_ = 0;
    int w_ = 0, h_ = 0;
};

// What the bench's hand-over modes (adopt, stage, render-process) give its frame loop: the
// program on screen is drawn elsewhere and presented on the render context.
class HandOverRun {
public:
    virtual ~HandOverRun() = default;
    // The scene's first program, and the target the frames are presented into on `gl` (the render
    // context, current; it is current again on return).
    virtual bool Start(HeadlessContext& gl, const std::string& scenePath, RenderPath path, int width, int height, std::string* error) = 0;
    // The reload step: a save starts a build elsewhere; a finished one goes on screen. True when
    // the program on screen changed.
    virtual bool Update(const std::vector<std::string>& changed, const std::string& scenePath, RenderPath path, std::string* error) = 0;
    // One frame: drawn where the program on screen lives, presented on the render context.
    virtual void Draw(const FrameInputs& in) = 0;
    // The frame's GPU work is done (the bench's glFinish): what waits for the gap between frames.
    virtual void FrameDone() {}
    // The program that went on screen last: its build, ms (with its load, first use and first
    // frame where the mode does those elsewhere).
    virtual double LastBuildMs() const = 0;
    // A line of the mode's own figures for the report, or "".
    virtual std::string Details() const { return ""; }
    // The program on screen is a quick first tier (an optimized one follows).
    virtual bool OnScreenQuick() const { return false; }
};

class AdoptRun : public HandOverRun {
public:
    // process: adopt-process (compiles there, loads on the new context); nullptr: adopt.
    explicit AdoptRun(CompileProcess* process) : process_(process) {}
    ~AdoptRun();
    AdoptRun(const AdoptRun&) = delete;
    AdoptRun& operator=(const AdoptRun&) = delete;
    // The scene's first program, built on `gl` (the render context, current), and the target the
    // frames are presented into there.
    bool Start(HeadlessContext& gl, const std::string& scenePath, RenderPath path, int width, int height, std::string* error) override;
    // The reload step: a save starts a build on a new context; a finished one goes on screen.
    // True when the program on screen changed. Runs with the render context current, leaves it so.
    bool Update(const std::vector<std::string>& changed, const std::string& scenePath, RenderPath path, std::string* error) override;
    // One frame: the scene on its program's context, then presented on the render context.
    void Draw(const FrameInputs& in) override;
    double LastBuildMs() const override { return program_->Origin().buildMs; }

private:
    bool UseContext(HeadlessContext* c, std::string* error);   // draw from now on with a renderer made on `c`
    bool StartWorker(std::string* error);                      // a new shared context and a thread on it

    CompileProcess* process_ = nullptr;
    uint64_t processTicket_ = 0;
    HeadlessContext* main_ = nullptr;                          // the render (window) context
    std::vector<std::unique_ptr<HeadlessContext>> contexts_;   // one per program, kept to the end
    // Each renderer with the context it was made on (its framebuffer and vertex array are that
    // context's): the last one draws.
    std::vector<std::pair<HeadlessContext*, std::unique_ptr<FrameRenderer>>> renderers_;
    std::unique_ptr<Program> program_;
    SceneInfo scene_;
    std::unique_ptr<CompileWorker> worker_;
    HeadlessContext* workerCtx_ = nullptr;
    uint64_t ticket_ = 0;
    ShaderSource pendingSrc_;
    SceneInfo pendingScene_;
    std::unique_ptr<PresentTarget> present_;   // on main_
    int w_ = 0, h_ = 0;
};

}  // namespace sdfvj
