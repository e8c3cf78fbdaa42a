#include "app/frame_hitch.h"

#include <fcntl.h>
#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <cstring>

namespace sdfvj {

FrameHitch::FrameHitch(double limitMs) : limitMs_(limitMs > 0 ? limitMs : 0) {
    if (On()) fd_ = ::open("/proc/thread-self/schedstat", O_RDONLY | O_CLOEXEC);   // the constructing (frame loop's) thread
}

FrameHitch::~FrameHitch() {
    if (fd_ >= 0) ::close(fd_);
}

// "<ns on a CPU> <ns waiting on a run queue> <timeslices>"
bool FrameHitch::ReadSched(uint64_t* runNs, uint64_t* waitNs) {
    if (fd_ < 0) return false;
    char text[128];
    const ssize_t n = ::pread(fd_, text, sizeof text - 1, 0);
    if (n <= 0) return false;
    const char* p = text;
    const char* end = text + n;
    auto r = std::from_chars(p, end, *runNs);
    if (r.ec != std::errc() || r.ptr == end || *r.ptr != ' ') return false;
    r = std::from_chars(r.ptr + 1, end, *waitNs);
    return r.ec == std::errc();
}

void FrameHitch::Begin(double now) {
    if (!On()) return;
    begin_ = now;
    frame_ = Account{};
    sched0_ = ReadSched(&run0_, &wait0_);
}

void FrameHitch::Stage(const char* name, double ms) {
    if (!On()) return;
    for (size_t i = 0; i < frame_.top.size(); ++i) {
        if (frame_.top[i].first && ms <= frame_.top[i].second) continue;
        for (size_t j = frame_.top.size() - 1; j > i; --j) frame_.top[j] = frame_.top[j - 1];
        frame_.top[i] = {name, ms};
        return;
    }
}

bool FrameHitch::End(double now, std::string* line) {
    if (!On()) return false;
    frame_.ms = (now - begin_) * 1000.0;
    if (frame_.ms > limitMs_) {
        uint64_t run = 0, wait = 0;
        if (sched0_ && ReadSched(&run, &wait) && run >= run0_ && wait >= wait0_) {
            frame_.runMs = (double)(run - run0_) / 1e6;
            frame_.waitMs = (double)(wait - wait0_) / 1e6;
        }
        if (frame_.ms > worst_.ms) worst_ = frame_;
        ++over_;
    }
    if (over_ == 0 || now - saidAt_ < 1.0) return false;
    *line = Describe(worst_, limitMs_, over_ - 1);
    saidAt_ = now;
    worst_ = Account{};
    over_ = 0;
    return true;
}

std::string FrameHitch::Describe(const Account& a, double limitMs, int more) {
    char text[400];
    int n = std::snprintf(text, sizeof text, "sdfvj live: a %.0f ms frame (--hitch-ms %g)", a.ms, limitMs);
    if (a.runMs >= 0) {
        const double blocked = a.ms - a.runMs - a.waitMs;
        n += std::snprintf(text + n, sizeof text - n, ": the show's thread ran %.0f ms, waited %.0f ms for a CPU, was blocked %.0f ms",
                           a.runMs, a.waitMs, blocked > 0 ? blocked : 0.0);
    }
    const char* sep = "; longest stages: ";
    for (const auto& [name, ms] : a.top) {
        if (!name || n >= (int)sizeof text) break;
        n += std::snprintf(text + n, sizeof text - n, "%s%s %.0f ms", sep, name, ms);
        sep = ", ";
    }
    if (more > 0 && n < (int)sizeof text)
        std::snprintf(text + n, sizeof text - n, " (and %d more over %g ms in the last second)", more, limitMs);
    return text;
}

}  // namespace sdfvj
