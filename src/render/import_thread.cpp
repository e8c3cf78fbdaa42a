#include "render/import_thread.h"

#include <epoxy/gl.h>
#include <unistd.h>

#include <chrono>

#include "render/shared_image.h"

namespace sdfvj {

bool ImportThread::Job::Done() {
    std::lock_guard<std::mutex> lock(mutex);
    return done;
}

bool ImportThread::Job::WaitDone(int timeoutMs) {
    std::unique_lock<std::mutex> lock(mutex);
    return wake.wait_for(lock, std::chrono::milliseconds(timeoutMs > 0 ? timeoutMs : 0), [this] { return done; });
}

bool ImportThread::Job::Abandon() {
    std::lock_guard<std::mutex> lock(mutex);
    abandoned = true;
    return done;
}

ImportThread::ImportThread(std::function<bool()> bind, std::function<void()> release, ImportOptions options)
    : options_(options), thread_([this, bind = std::move(bind), release = std::move(release)] { Run(bind, release); }) {}

ImportThread::~ImportThread() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

bool ImportThread::Ok() {
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait(lock, [this] { return started_; });
    return ok_;
}

std::shared_ptr<ImportThread::Job> ImportThread::Import(int fd0, int fd1, int images, uint64_t size, int width, int height) {
    auto job = std::make_shared<Job>();
    job->fds[0] = fd0;
    job->fds[1] = fd1;
    job->images = images;
    job->size = size;
    job->width = width;
    job->height = height;
    Enqueue(job);
    return job;
}

void ImportThread::Free(const unsigned textures[2], const unsigned memories[2], void* fence) {
    auto job = std::make_shared<Job>();
    for (int i = 0; i < 2; ++i) {
        job->textures[i] = textures[i];
        job->memories[i] = memories[i];
    }
    job->fence = fence;
    Enqueue(std::move(job));
}

void ImportThread::Enqueue(std::shared_ptr<Job> job) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        job->frame = frames_;
        job->queued = std::chrono::steady_clock::now();
        queue_.push_back(std::move(job));
    }
    wake_.notify_all();
}

void ImportThread::FrameDone() {   // every frame of the show: wakes the thread only when a job waits
    bool waiting = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        ++frames_;
        waiting = !queue_.empty();
    }
    if (waiting) wake_.notify_all();
}

bool ImportThread::Startable(std::chrono::steady_clock::time_point now) const {
    // Gated once frames are told (frames_ > 0): a job waits for the end of the frame it was queued
    // in, or kMaxHoldMs (a caller polling without frames is never held up longer).
    if (queue_.empty()) return false;
    const Job& front = *queue_.front();
    return !options_.afterFrame || frames_ == 0 || front.frame < frames_ ||
           now - front.queued >= std::chrono::milliseconds(ImportOptions::kMaxHoldMs);
}

namespace {
void FreeJob(ImportThread::Job& job) {
    for (int i = 0; i < 2; ++i) {
        if (job.textures[i]) glDeleteTextures(1, &job.textures[i]);
        if (job.memories[i]) glDeleteMemoryObjectsEXT(1, &job.memories[i]);
        job.textures[i] = job.memories[i] = 0;
    }
}
}  // namespace

void ImportThread::Run(std::function<bool()> bind, std::function<void()> release) {
    const bool ok = bind();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        started_ = true;
        ok_ = ok;
    }
    wake_.notify_all();
    unsigned scratch = 0;   // the one-pixel target of each image's first use
    for (;;) {
        std::shared_ptr<Job> job;
        bool stopping = false;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            while (!stop_ && !Startable(std::chrono::steady_clock::now())) {
                if (queue_.empty()) wake_.wait(lock);
                else wake_.wait_until(lock, queue_.front()->queued + std::chrono::milliseconds(ImportOptions::kMaxHoldMs));
            }
            if (queue_.empty()) break;   // stopping, nothing left
            job = std::move(queue_.front());
            queue_.pop_front();
            stopping = stop_;
        }
        if (job->fence) {   // a free: after the render thread's last read (the render context flushed it)
            if (ok) {
                glClientWaitSync((GLsync)job->fence, 0, 5000000000ull);
                glDeleteSync((GLsync)job->fence);
                FreeJob(*job);
            }
            ++freed_;
            continue;
        }
        const auto t0 = std::chrono::steady_clock::now();
        bool abandoned = false;
        {
            std::lock_guard<std::mutex> lock(job->mutex);
            abandoned = job->abandoned;
        }
        if (!ok || stopping || abandoned) {
            for (int fd : job->fds)
                if (fd >= 0) ::close(fd);
            job->why = ok ? "the import thread was ended" : "the import thread has no GL context";
        } else {
            job->textures[0] = ImportSharedTexture(job->fds[0], job->size, job->width, job->height, &job->memories[0], &job->why);
            if (job->images == 2) {
                if (job->textures[0])
                    job->textures[1] = ImportSharedTexture(job->fds[1], job->size, job->width, job->height, &job->memories[1], &job->why);
                else
                    ::close(job->fds[1]);
            }
            if (!job->textures[0] || (job->images == 2 && !job->textures[1])) FreeJob(*job);
            if (options_.touch && job->textures[0]) {
                if (!scratch) {
                    glGenTextures(1, &scratch);
                    glBindTexture(GL_TEXTURE_2D, scratch);
                    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, 1, 1);
                }
                for (unsigned t : job->textures)
                    if (t) glCopyImageSubData(t, GL_TEXTURE_2D, 0, 0, 0, 0, scratch, GL_TEXTURE_2D, 0, 0, 0, 0, 1, 1, 1);
            }
            glFinish();   // the render thread's context draws from them next
        }
        job->ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        {
            std::lock_guard<std::mutex> lock(job->mutex);
            if (job->abandoned) FreeJob(*job);
            ++imported_;
            job->done = true;
        }
        job->wake.notify_all();
    }
    if (scratch) glDeleteTextures(1, &scratch);
    if (release) release();
}

}  // namespace sdfvj
