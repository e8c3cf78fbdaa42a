// IsfHost: the post chain a show draws, built where no frame waits for it (issue 12).
//
// A driver may compile a program's pixel code at its first draw in each context: on llvmpipe,
// bloom's first draw takes 120-360 ms, and a program drawn first in a second, shared context
// still costs the render thread's context nearly all of it again (100 against 118 ms, measured).
// So the chain has two contexts of its own (sharing objects with the render thread's), each
// current for good on a thread of its own. The thread of the spare context builds a new chain and
// draws it once at the show's size with the show's kind of input. On such a renderer each frame
// the render thread hands the thread of the chain on screen its input between two fences; on
// others the render thread draws the chain itself (IsfDrawIn: no context switch each frame, which
// cost NVIDIA 0.4-0.8 ms). After a swap the new
// chain takes the old one's feedback and the old chain's textures go to a pool the
// next build draws into: on NVIDIA a new texture's first draw holds every context's frames for
// about 1 ms per MB (IsfTexturePool).
//
//   IsfHost host({ctxA, ctxB});
//   host.Request(files, w, h);                   // files parsed already (LoadIsfFile)
//   each frame: host.Poll(&done); out = host.Render(sceneTexture, w, h, in);
//   on a file change: host.Reload(&errors);      // changed stages rebuilt, broken ones keep their last good file
//
// Without contexts of its own (none given, or one cannot be made current) the chain is built and
// drawn in the render thread's context, and a build holds that frame. Render thread only.
#pragma once
#include <array>
#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "isf/isf.h"

namespace sdfvj {

// Where a chain built in the host's own contexts is drawn each frame.
enum class IsfDrawIn {
    Auto,           // RenderThread, or OwnContexts on a renderer that compiles a program's pixel code
                    // again in each context (Mesa's llvmpipe and softpipe); SDFVJ_POST_DRAW=own|render forces one
    OwnContexts,    // by the thread of the chain's own context, the render thread handing it each frame's
                    // input between two fences: no frame compiles, but every frame switches contexts
                    // (NVIDIA: 0.4-0.8 ms a frame; llvmpipe: within 1-4 %)
    RenderThread,   // in the render thread's context (its vertex arrays and framebuffers made there at its
                    // first draw): no switch; the first draw there finishes the program for that context
};

struct IsfHostContext {
    std::function<bool()> makeCurrent;   // on the calling thread; false if it could not be
    std::function<void()> release;       // no context current on the calling thread
};

class IsfHost {
public:
    IsfHost();   // builds and draws in the render thread's context
    explicit IsfHost(std::array<IsfHostContext, 2> contexts, IsfDrawIn drawIn = IsfDrawIn::Auto);   // render thread, its context current
    ~IsfHost();   // render thread, its own context current
    IsfHost(const IsfHost&) = delete;
    IsfHost& operator=(const IsfHost&) = delete;

    bool OwnContexts() const { return own_; }
    // Where the chains are drawn (Auto resolved): OwnContexts or RenderThread with contexts of its
    // own, RenderThread without.
    IsfDrawIn DrawIn() const { return own_ && !drawHere_ ? IsfDrawIn::OwnContexts : IsfDrawIn::RenderThread; }
    // The chain of these files (an empty list: none). With contexts of its own it returns at
    // once and the chain on screen keeps drawing until the new one is built; Poll says when.
    void Request(std::vector<IsfFile> files, int w, int h);
    // A watched file changed: each stage whose file's bytes changed and still parses is rebuilt
    // with the rest in a new chain; one that does not parse adds a "file:line: ..." line to
    // `errors` and keeps its last good file. A change only the header sees (the GLSL is the
    // program's) is applied to the chain on screen and compiles nothing. True when a rebuild started.
    bool Reload(std::vector<std::string>* errors);

    struct Done {
        bool adopted = false;              // a new chain is on screen
        std::vector<std::string> errors;   // "file:line: ..." of what did not build (the chain on screen stays)
        double buildMs = 0.0;              // build and first draw, on the worker
        double adoptMs = 0.0;              // on the render thread: feedback copied, the old chain deleted
    };
    // Each frame, before Render: true when a requested build finished (adopted or failed).
    bool Poll(Done* done);
    bool Busy() const;
    // The chain on screen (may be empty) and the files the latest request or reload asked for.
    const IsfChain& Chain() const { return *chain_; }
    const std::vector<IsfFile>& Wanted() const { return wanted_; }
    // Runs the chain on screen over `input` (w x h) and returns its output texture (shared with
    // the render thread's context, valid until the next Render); `input` when the chain is empty.
    unsigned Render(unsigned input, int w, int h, const IsfFrameInputs& in);
    // Chains built so far (adopted or not): a save that changes only the header builds none.
    int ChainsBuilt() const { return built_.load(); }
    // A build that had to make new render targets (the first, or one at a new size) draws them
    // twice (both textures of each double-buffered target) and, with spare targets on, makes and
    // draws a second set for the pool, which the next build takes: so the first save draws into no
    // new texture either (H100, feedback_trails at 4K: the first save 144-268 -> 11 ms, the first
    // build's frame on screen 9 -> 7 ms; docs/performance.md, "Session 33"). Drawn in the build's
    // context only: drawing it in the render thread's too was measured and cost that frame more.
    // Default: on, except on Mesa's software rasterizers, where a new texture costs nothing;
    // SDFVJ_POST_SPARE=0|1 forces. Before the first Request.
    void SetSpareTargets(bool on) { spare_ = on; }
    bool SpareTargets() const { return spare_; }
    // What the show's frames will hand the chain, for the builds before the first frame: the
    // input's internal format (GL_RGBA8, say; 0: none) and the audio textures' lengths (0: no
    // audio). A build's first draw is drawn as the last frame was; before any frame, as this says
    // (and at Request's size). On llvmpipe a draw with another input, another kind of size (a
    // power of two or not) or other audio textures is another variant of the program, compiled at
    // that draw: the show's first frame with the chain paid it (450 ms in the soak's first second).
    void SetFrameHint(unsigned inputFormat, int waveSamples, int spectrumBins) {
        if (!lastFormat_) lastFormat_ = inputFormat;
        if (!lastWave_) lastWave_ = waveSamples;
        if (!lastSpectrum_) lastSpectrum_ = spectrumBins;
    }
    // Every chain keeps the render targets of its last `n` other sizes (IsfEffect::SetKeptSizes).
    // Before the first Request.
    void SetKeptSizes(int n) { keepSizes_ = n; }
    // Render targets the builds had to make new so far (not taken from the pool).
    int TargetsMade() const { return pool_.Misses(); }
    // Where the last Render's time went (ms): handing over to the chain's thread and back, and
    // the chain's draw calls there.
    struct Split {
        double handover = 0.0, draw = 0.0;
    };
    const Split& LastSplit() const { return split_; }

private:
    struct Job {
        std::vector<IsfFile> files, fallback;   // fallback[i]: stage i's last good file (empty path: none)
        int w = 0, h = 0;
        unsigned inputFormat = 0;               // 0: no input (a generator)
        int waveSamples = 0, spectrumBins = 0;  // the audio the last frame had (0: silence)
    };
    struct Result {
        std::unique_ptr<IsfChain> chain;
        std::vector<IsfFile> files;             // what each stage was built from
        std::vector<std::string> errors;
        double buildMs = 0.0;
        bool spareMade = false;                 // the build put a spare set of targets in the pool
        bool done = false;
    };
    void Submit(std::vector<IsfFile> files, std::vector<IsfFile> fallback);
    void Build(const Job& job, Result* out);   // on the context current on the calling thread
    void Adopt(Result& r);
    void Retire(std::unique_ptr<IsfChain> chain, int context, bool pool);   // pool: its textures to pool_
    void Pool(IsfChain& retired);              // its textures to pool_, on the thread of its context
    class ContextThread;                       // a thread keeping one context current, running tasks in order
    std::array<std::unique_ptr<ContextThread>, 2> threads_;
    // The retired chain's render targets, which the next build takes (IsfTexturePool says why), and
    // the input its first draw reads, kept from build to build for the same reason. Builds run one
    // at a time.
    IsfTexturePool pool_;
    struct Scratch {
        unsigned texture = 0, format = 0;
        int w = 0, h = 0;
    } buildInput_;
    std::unique_ptr<IsfChain> copyFrom_;       // the chain a swap replaced, until the first frame copied its feedback
    bool copyFromPool_ = true;                 // its textures go to the pool (not when the new chain's build made a spare set)

    bool own_ = false;
    bool drawHere_ = false;                    // built in its own contexts, drawn in the render thread's (IsfDrawIn::RenderThread)
    int current_ = 0;                          // the context the chain on screen lives in
    std::unique_ptr<IsfChain> chain_;
    std::vector<IsfFile> shown_;               // the files of the chain on screen
    std::vector<IsfFile> wanted_;              // the latest request (last good per stage)
    std::vector<uint64_t> hashes_;             // IsfFilesHash of each wanted file when last read
    bool queued_ = false;                      // a request came while a build ran
    std::vector<IsfFile> queuedFallback_;
    std::atomic<int> built_{0};
    bool spare_ = false;
    int keepSizes_ = 0;
    Split split_;
    // The last frame's input, which the next build's first draw copies.
    unsigned lastInput_ = 0, lastFormat_ = 0;
    int lastW_ = 0, lastH_ = 0, lastWave_ = 0, lastSpectrum_ = 0;

    mutable std::mutex mutex_;                 // result_ and running_: the build threads write them
    Result result_;
    bool running_ = false;
};

}  // namespace sdfvj
