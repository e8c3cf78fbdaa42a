// ImportThread: a thread with a GL context of its own, sharing objects with the render thread's,
// that imports a render server's frame images (render/shared_image.h, GL_EXT_memory_object_fd) so
// that the frame which puts a new server on screen does not import them itself (issue 12).
//
// Why: on the NVIDIA H200 the frame in which a new server's answer arrived was a reload's longest,
// 1.2-2.3 ms against a 0.44-0.56 ms steady frame; reading the answer and importing its two images
// took 0.63-0.78 ms of it (docs/performance.md, session 19). Textures and memory objects are shared
// objects, so a texture made on this thread's context is drawn from on the render thread's; the
// thread finishes (glFinish) each import before it says it is done. It also uses each image once
// (a one-pixel copy: whatever the driver does at an image's first use happens here), and frees
// the images of a server the show has stopped, once the render thread's last read of them is done
// (a fence), so that the frame which retires a server frees nothing either.
//
//   ImportThread importer([&] { return shared.MakeCurrent(); }, [&] { shared.ReleaseCurrent(); });
//   process.SetImporter(&importer);   // RenderProcess::PollReady hands its vkmem images over to it
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace sdfvj {

// What the thread does besides importing (bench reload's render-process-free-here and
// render-process-no-touch turn one off, to measure it).
struct ImportOptions {
    bool touch = true;      // each imported image used once (a one-pixel copy) before it is handed over
    bool freeThere = true;  // RenderProcess::Stop hands its images to Free
    // Once the show says its frames end (FrameDone), a job queued during a frame starts after that
    // frame's GPU work is done, in the gap before the next, not beside it, or after kMaxHoldMs if
    // no frame ends before (false: at once).
    bool afterFrame = true;
    static constexpr int kMaxHoldMs = 100;
};

class ImportThread {
public:
    // One request: a server's images (1 or 2 fds of `size` bytes each, width x height RGBA8).
    struct Job {
        int fds[2] = {-1, -1};
        int images = 1;
        uint64_t size = 0;
        int width = 0, height = 0;
        // Set by the thread, read once Done():
        unsigned textures[2] = {0, 0}, memories[2] = {0, 0};
        std::string why;     // why an import failed (textures[0] is then 0)
        double ms = 0;       // on the thread: the imports and the glFinish after them
        bool Done();
        bool WaitDone(int timeoutMs);
        // The caller no longer wants it (its server was stopped): the thread frees what it made.
        // Returns true when the job was done (its textures are the caller's to free), false when
        // the thread will free them.
        bool Abandon();

    private:
        friend class ImportThread;
        std::mutex mutex;
        std::condition_variable wake;
        bool done = false, abandoned = false;
        void* fence = nullptr;   // a free job (textures and memories given): wait for it, then delete
        uint64_t frame = 0;      // the frames ended (FrameDone) when it was queued
        std::chrono::steady_clock::time_point queued;
    };

    // bind runs once on the thread and must make a context current there that shares objects with
    // the render thread's; release runs when the thread ends.
    ImportThread(std::function<bool()> bind, std::function<void()> release = {}, ImportOptions options = {});
    ~ImportThread();   // ends the thread; jobs not yet started are abandoned (their fds closed)
    ImportThread(const ImportThread&) = delete;
    ImportThread& operator=(const ImportThread&) = delete;
    bool Ok();   // the context was made current (waits for the thread to say so)
    // Queues a job (fds taken: closed by the thread whatever happens). Never blocks.
    std::shared_ptr<Job> Import(int fd0, int fd1, int images, uint64_t size, int width, int height);
    // Frees textures and their memory objects (GL names of the shared context) once `fence` (a
    // GLsync of the render thread's context, flushed; taken) has signalled. Never blocks.
    void Free(const unsigned textures[2], const unsigned memories[2], void* fence);
    // The show's frame is done (its GPU work finished, or presented): jobs queued until now may start.
    // Until the first call nothing waits (a user without frames is never held up).
    void FrameDone();
    const ImportOptions& Settings() const { return options_; }
    int Imported() const { return imported_; }   // import jobs done, for tests
    int Freed() const { return freed_; }         // free jobs done, for tests

private:
    void Run(std::function<bool()> bind, std::function<void()> release);
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::shared_ptr<Job>> queue_;
    bool stop_ = false, started_ = false, ok_ = false;
    uint64_t frames_ = 0;   // FrameDone calls
    ImportOptions options_;
    bool Startable(std::chrono::steady_clock::time_point now) const;   // mutex_ held: the front job may start
    void Enqueue(std::shared_ptr<Job> job);   // stamped with the frame and time it was queued
    std::atomic<int> imported_{0}, freed_{0};
    std::thread thread_;
};

}  // namespace sdfvj
