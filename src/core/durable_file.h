// What the crash-safe recorders share (TakeRecorder: the take's SMF; WavRecorder: the audio WAV
// beside it): a positioned write that finishes or says it failed, and a thread that calls a
// flush every N seconds until stopped. Each recorder keeps its own write order (data, fdatasync,
// then the header that covers it), which is what makes its file survive a crash.
//
//   PeriodicFlush flusher;
//   flusher.Start(0.5, [this] { WritePending(); });   // on its own thread, every 0.5 s
//   flusher.Stop();                                    // joins; the caller then writes the rest
#pragma once
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>

namespace sdfvj {

// pwrite until all `n` bytes are at `offset` (retries EINTR and short writes); false on an error
// (errno says which).
inline bool PwriteAll(int fd, const uint8_t* p, size_t n, uint64_t offset) {
    while (n > 0) {
        const ssize_t w = ::pwrite(fd, p, n, off_t(offset));
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= size_t(w);
        offset += uint64_t(w);
    }
    return true;
}

// Calls `flush` every `seconds` on its own thread until Stop() (or destruction); Stop() wakes it
// at once and joins, without a last call.
class PeriodicFlush {
public:
    PeriodicFlush() = default;
    ~PeriodicFlush() { Stop(); }
    PeriodicFlush(const PeriodicFlush&) = delete;
    PeriodicFlush& operator=(const PeriodicFlush&) = delete;

    void Start(double seconds, std::function<void()> flush) {
        Stop();
        stop_ = false;
        thread_ = std::thread([this, seconds, flush = std::move(flush)] {
            const auto interval = std::chrono::duration<double>(seconds);
            std::unique_lock<std::mutex> lock(mutex_);
            while (!stop_) {
                wake_.wait_for(lock, interval, [this] { return stop_; });
                if (stop_) break;
                lock.unlock();
                flush();
                lock.lock();
            }
        });
    }
    void Stop() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        if (thread_.joinable()) thread_.join();
    }

private:
    std::thread thread_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;   // guarded by mutex_
};

}  // namespace sdfvj
