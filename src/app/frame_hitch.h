// A frame of `sdfvj live` that took too long, told where its time went (`--hitch-ms`).
//
// Each stage of the frame loop is timed (LiveSession::Guard), and the show's thread's scheduler
// counters (/proc/thread-self/schedstat: time on a CPU, time runnable but waiting for one) are read
// once a frame. A frame over the limit is kept; at most once a second the longest one kept is said
// as one line: how long, how much of it the thread ran, waited for a CPU (a machine too loaded:
// render processes compiling, llvmpipe's threads) or was blocked (the GPU, a render process, a
// file), and its five longest stages (a part of a stage, `reload: post`, listed beside the
// stage). A VJ's technician reads which it was; the soak (scripts/soak.sh) prints these lines.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <string>

namespace sdfvj {

class FrameHitch {
public:
    explicit FrameHitch(double limitMs);   // 0: off
    ~FrameHitch();
    FrameHitch(const FrameHitch&) = delete;
    FrameHitch& operator=(const FrameHitch&) = delete;

    bool On() const { return limitMs_ > 0; }
    // Times a scope as a stage: Done(), or the end of the scope however it ends. A null hitch: nothing.
    class Scope {
    public:
        Scope(FrameHitch* hitch, const char* name) : hitch_(hitch), name_(name), t0_(std::chrono::steady_clock::now()) {}
        ~Scope() { Done(); }
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;
        void Done() {
            if (hitch_) hitch_->Stage(name_, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_).count());
            hitch_ = nullptr;
        }

    private:
        FrameHitch* hitch_;
        const char* name_;
        std::chrono::steady_clock::time_point t0_;
    };
    void Begin(double now);                       // the frame starts (the show's wall clock, s)
    void Stage(const char* name, double ms);      // a stage of it took ms
    // The frame ends at `now`: true with *line set when a hitch is due to be said.
    bool End(double now, std::string* line);

    // One frame's account, kept while it is the longest of the second.
    struct Account {
        double ms = 0, runMs = -1, waitMs = -1;   // wall; on a CPU and waiting for one (-1: no schedstat)
        std::array<std::pair<const char*, double>, 5> top{};   // the longest stages, longest first
    };
    static std::string Describe(const Account& a, double limitMs, int more);

private:
    bool ReadSched(uint64_t* runNs, uint64_t* waitNs);

    double limitMs_;
    int fd_ = -1;                 // /proc/thread-self/schedstat of the show's thread
    double begin_ = 0;
    uint64_t run0_ = 0, wait0_ = 0;
    bool sched0_ = false;
    Account frame_;               // the frame being timed
    Account worst_;               // the longest over the limit since the last line
    int over_ = 0;                // frames over the limit since the last line
    double saidAt_ = -1e9;
};

}  // namespace sdfvj
