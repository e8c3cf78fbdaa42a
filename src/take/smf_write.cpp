// Whole-take SMF writer (format 0, kTakeSecondsPerTick per tick) and the replay cursor.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "take/smf_bytes.h"
#include "take/take.h"

namespace sdfvj {

double QuantizeTakeTime(double seconds) {
    // Same arithmetic as the reader: ticks * tempo / (ppq * 1e6), one rounding.
    return double(smf::SecondsToTicks(seconds)) * double(kTakeTempoMicroseconds) /
           (double(kTakeTicksPerQuarter) * 1.0e6);
}

std::vector<uint8_t> EncodeTake(const Take& take) {
    std::vector<uint8_t> track = smf::TrackPrologue("sdfvj take");
    int64_t last = 0;
    for (const ControlEvent& e : take.events) {
        const int64_t tick = std::max(last, smf::SecondsToTicks(e.time));
        if (smf::PutEvent(&track, tick - last, e)) last = tick;
    }
    smf::PutEndOfTrack(&track, std::max<int64_t>(0, smf::SecondsToTicks(take.duration) - last));
    std::vector<uint8_t> file = smf::HeaderChunk();
    file.insert(file.end(), {'M', 'T', 'r', 'k'});
    smf::PutU32(&file, uint32_t(track.size()));
    file.insert(file.end(), track.begin(), track.end());
    return file;
}

bool WriteTake(const std::string& path, const Take& take, std::string* error) {
    const std::vector<uint8_t> bytes = EncodeTake(take);
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) {
        if (error) *error = path + ": cannot open for writing: " + std::strerror(errno);
        return false;
    }
    const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    const bool closed = std::fclose(f) == 0;
    if (!(ok && closed)) {
        if (error) *error = path + ": write failed: " + std::strerror(errno);
        return false;
    }
    return true;
}

// ---- ReplayCursor ------------------------------------------------------------------------

size_t ReplayCursor::Until(double t, std::vector<ControlEvent>* out) {
    const size_t first = next_;
    const std::vector<ControlEvent>& events = take_->events;
    while (next_ < events.size() && events[next_].time < t) out->push_back(events[next_++]);
    return next_ - first;
}

std::vector<ControlEvent> ReplayCursor::Until(double t) {
    std::vector<ControlEvent> out;
    Until(t, &out);
    return out;
}

double ReplayCursor::NextTime() const {
    return Done() ? take_->duration : take_->events[next_].time;
}

}  // namespace sdfvj
