// CompileWorker: compiles and links shader programs on a thread of its own, with a GL context
// that shares objects with the render thread's, so a reload never stalls a frame (drivers that
// advertise GL_KHR_parallel_shader_compile still block one frame on link or first use: ~0.2 s
// on the H100, the whole compile on llvmpipe). The worker also draws each new program once
// into a 1x1 target, so the driver's lazy back-end compile happens there too.
//
//   CompileWorker worker([&] { return sharedContext.MakeCurrent(); });   // binder runs on the worker
//   PendingProgram::SetWorker(&worker);   // from now on PendingProgram::Begin() queues here
//
// Program objects are shared between the two contexts; the render thread adopts the finished
// program name (Program::Adopt). Thread-safe; one job at a time, in order.
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>
#include <thread>

#include "shader/shader.h"

namespace sdfvj {

// Compiles and links on the calling thread's context; 0 and the driver's raw log on failure.
// `retrievable` asks for GL_PROGRAM_BINARY_RETRIEVABLE_HINT (the binary is read back).
unsigned CompileLinkHere(const std::string& text, RenderPath path, std::string* rawLog, bool retrievable);
// Runs the program once into a 1x1 target so the driver finishes its lazy back-end compile here
// rather than on the render thread's first draw. Uniforms are zero: the shader exits early.
void PrimeProgram(unsigned prog, RenderPath path, bool floatImage);

class CompileWorker {
public:
    // `bindContext` runs once on the worker thread and must make a shared context current there.
    // With `handOverBinary` the worker's context need not be shared: each linked program is
    // read back with glGetProgramBinary and deleted there, and Finish() loads the binary on the
    // render thread's context (no object crosses contexts, so no share-group lock).
    // `releaseContext` runs on the worker thread as it ends, after the worker deleted the programs
    // nobody took: it must make no context current there (a thread that ends with a context still
    // current leaks the driver's per-thread state).
    explicit CompileWorker(std::function<bool()> bindContext, bool handOverBinary = false,
                           std::function<void()> releaseContext = {});
    ~CompileWorker();
    CompileWorker(const CompileWorker&) = delete;
    CompileWorker& operator=(const CompileWorker&) = delete;
    // False when the worker's context could not be made current (then nothing is compiled here).
    bool Ok();
    // Queues a compile of `text`. With `store`, a program that links is also written to the
    // on-disk program cache (program_cache.h) from this thread, off the render thread's time.
    uint64_t Submit(const std::string& text, RenderPath path, bool store = false);
    // Queues a load of a program binary (the compile process's, or the program cache's) on the
    // worker's context, which must share objects with the render thread's: glProgramBinary, then
    // one 1x1 use (PrimeProgram) and glFinish, so the driver's lazy finalization at first use
    // (150-600 ms on NVIDIA, issue 12) happens here and not in the render thread's next frame.
    // Result::program is the used program; 0 with `refused` when the driver refused the binary.
    uint64_t SubmitLoad(unsigned format, std::vector<uint8_t> binary, RenderPath path, bool floatImage);
    // What a finished ticket gives back.
    struct Result {
        unsigned program = 0;            // the linked program (0 on failure, or in binary mode)
        std::string log;                 // the driver's raw messages on failure
        std::vector<uint8_t> binary;     // binary mode: the program binary, and its format
        unsigned format = 0;
        bool noBinary = false;           // binary mode, but the driver gave none (GL_PROGRAM_BINARY_LENGTH 0,
                                         // Mesa with its disk cache off): the caller compiles it itself
        double buildMs = 0.0;            // compile + link (+ priming draw) on the worker; a load: load + first use
        bool refused = false;            // a load the driver refused (glProgramBinary did not link)
        bool used = false;               // the program was used once here (PrimeProgram) before the hand-over
    };
    // True once the ticket is done, filling `result`. A ticket is reported once.
    bool Poll(uint64_t ticket, Result* result);
    // The caller no longer wants this ticket; its program is deleted when done.
    void Forget(uint64_t ticket);
    // After its jobs, once none came for kTrimDelayMs, the heap's freed pages go back to the system
    // (glibc malloc_trim, every arena), on this thread: a compile frees tens of MB that glibc would
    // keep mapped. Not on the render thread, where the trim held the frame that put a program on
    // screen 8-22 ms (llvmpipe, `bench reload --modes worker`); and not beside the render thread's
    // first draw of the program it handed over, which a trim at once slowed 2-4x (the draw took
    // its memory back from the system, page by page). Under a stream of jobs, at least every
    // kTrimEveryMs, between two of them. Off by default.
    void SetTrimAfterJobs(bool on) { trimAfterJobs_ = on; }
    bool TrimAfterJobs() const { return trimAfterJobs_.load(); }
    int Trims() const { return trims_.load(); }   // trims run so far

private:
    struct Job {
        uint64_t ticket;
        std::string text;
        RenderPath path;
        bool store;
        bool load = false;               // SubmitLoad: `binary` in `format`, no compile
        unsigned format = 0;
        std::vector<uint8_t> binary;
        bool floatImage = false;
    };
    using Done = Result;
    void Loop(std::function<bool()> bind, std::function<void()> release);
    void TrimSoon();   // mutex_ held
    static constexpr int kTrimDelayMs = 500, kTrimEveryMs = 5000;

    std::mutex mutex_;
    std::condition_variable wake_, started_;
    std::deque<Job> jobs_;
    std::map<uint64_t, Done> done_;
    std::map<uint64_t, bool> forgotten_;
    uint64_t next_ = 1;
    int state_ = 0;          // 0 starting, 1 running, -1 no context
    bool stop_ = false;
    std::atomic<bool> trimAfterJobs_{false};
    std::atomic<int> trims_{0};
    std::optional<std::chrono::steady_clock::time_point> trimAt_;   // a trim due then (mutex_)
    std::chrono::steady_clock::time_point lastTrim_;                 // this thread's
    bool handOverBinary_ = false;
    std::thread thread_;
};

}  // namespace sdfvj
