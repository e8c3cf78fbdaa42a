// EventQueue: a mutex-guarded deque. The critical sections are a push_back or a splice of the
// ready prefix, so neither side holds the lock for longer than a few hundred nanoseconds.
#include "control/control.h"

namespace sdfvj {

void EventQueue::Push(ControlEvent e) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (events_.size() >= capacity_) {
        dropped_.fetch_add(1);
        return;
    }
    events_.push_back(std::move(e));
    pushed_.fetch_add(1);
}

std::vector<ControlEvent> EventQueue::DrainUntil(double time) {
    std::vector<ControlEvent> out;
    std::lock_guard<std::mutex> lock(mutex_);
    // Producers push in their own clock order; two producers may interleave a little out of
    // order, so stop at the first event that is not due yet rather than scanning past it.
    while (!events_.empty() && events_.front().time <= time) {
        out.push_back(std::move(events_.front()));
        events_.pop_front();
    }
    return out;
}

size_t EventQueue::Size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return events_.size();
}

}  // namespace sdfvj
