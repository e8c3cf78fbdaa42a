// TakeRecorder: append-only SMF writing that keeps the file on disk readable at all times.
//
// File: MThd | MTrk <length> | tempo, name | events... | 00 FF 2F 00 (End-of-Track)
// Each write (writer thread, every flushInterval, or Flush()):
//   1. pwrite the new events followed by a fresh End-of-Track over the old End-of-Track;
//   2. fdatasync, so the events are on disk before the length that covers them;
//   3. pwrite the new MTrk length; fdatasync.
// A crash between 1 and 3 leaves the old length: the reader keeps every event it covers and
// warns about the cut (see docs/takes.md). The render thread never waits for the disk.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>

#include "core/durable_file.h"
#include "take/smf_bytes.h"
#include "take/take.h"

namespace sdfvj {

static constexpr uint64_t kTrackLengthOffset = 18;  // after "MThd" + 6-byte header + "MTrk"
static constexpr uint64_t kTrackDataOffset = 22;

TakeRecorder::~TakeRecorder() { Close(); }

bool TakeRecorder::Open(const std::string& path, std::string* error) {
    return Open(path, TakeRecorderDesc{}, error);
}

bool TakeRecorder::Open(const std::string& path, const TakeRecorderDesc& desc, std::string* error) {
    Close();
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) {
        if (error) *error = path + ": cannot open for recording: " + std::strerror(errno);
        return false;
    }
    std::vector<uint8_t> head = smf::HeaderChunk();
    const std::vector<uint8_t> prologue = smf::TrackPrologue(desc.trackName);
    head.insert(head.end(), {'M', 'T', 'r', 'k'});
    smf::PutU32(&head, uint32_t(prologue.size() + 4));
    head.insert(head.end(), prologue.begin(), prologue.end());
    smf::PutEndOfTrack(&head, 0);
    if (!PwriteAll(fd, head.data(), head.size(), 0)) {
        if (error) *error = path + ": write failed: " + std::strerror(errno);
        ::close(fd);
        return false;
    }
    ::fdatasync(fd);
    fd_ = fd;
    path_ = path;
    desc_ = desc;
    if (desc_.flushInterval <= 0.0) desc_.flushInterval = 0.5;
    eotOffset_ = kTrackDataOffset + prologue.size();
    {
        std::lock_guard<std::mutex> lock(pendingMutex_);
        pending_.clear();
        lastTick_ = 0;
        error_.clear();
    }
    recorded_ = 0;
    dropped_ = 0;
    open_ = true;
    flusher_.Start(desc_.flushInterval, [this] { WritePending(-1); });
    return true;
}

void TakeRecorder::Record(const ControlEvent& e) {
    if (!open_.load(std::memory_order_acquire)) {
        ++dropped_;
        return;
    }
    std::lock_guard<std::mutex> lock(pendingMutex_);
    const int64_t tick = std::max(lastTick_, smf::SecondsToTicks(e.time - desc_.timeOrigin));
    if (smf::PutEvent(&pending_, tick - lastTick_, e)) {
        lastTick_ = tick;
        ++recorded_;
    } else {
        ++dropped_;
    }
}

void TakeRecorder::Flush() {
    if (fd_ >= 0) WritePending(-1);
}

void TakeRecorder::Close() { Close(-1.0e300); }

void TakeRecorder::Close(double endTime) {
    if (fd_ < 0) return;
    open_ = false;
    flusher_.Stop();
    const int64_t endTick = endTime < -1.0e299 ? -1 : smf::SecondsToTicks(endTime - desc_.timeOrigin);
    WritePending(endTick);
    ::close(fd_);
    fd_ = -1;
}

std::string TakeRecorder::Error() const {
    std::lock_guard<std::mutex> lock(pendingMutex_);
    return error_;
}

void TakeRecorder::SetError(const std::string& e) {
    std::lock_guard<std::mutex> lock(pendingMutex_);
    if (error_.empty()) error_ = e;
}

void TakeRecorder::WritePending(int64_t endTick) {
    std::lock_guard<std::mutex> io(io_);
    std::vector<uint8_t> bytes;
    int64_t lastTick;
    {
        std::lock_guard<std::mutex> lock(pendingMutex_);
        bytes.swap(pending_);
        lastTick = lastTick_;
    }
    if (bytes.empty() && endTick < 0) return;
    const size_t eventBytes = bytes.size();
    smf::PutEndOfTrack(&bytes, endTick < 0 ? 0 : std::max<int64_t>(0, endTick - lastTick));
    // 1. events + End-of-Track over the old End-of-Track; 2. sync; 3. length that covers them.
    if (!PwriteAll(fd_, bytes.data(), bytes.size(), eotOffset_)) {
        SetError(path_ + ": write failed: " + std::strerror(errno) + "; these events are lost, later writes are tried");
        return;
    }
    ::fdatasync(fd_);
    const uint64_t trackLength = eotOffset_ + bytes.size() - kTrackDataOffset;
    std::vector<uint8_t> length;
    smf::PutU32(&length, uint32_t(trackLength));
    if (!PwriteAll(fd_, length.data(), length.size(), kTrackLengthOffset)) {
        SetError(path_ + ": write failed: " + std::strerror(errno));
        return;
    }
    ::fdatasync(fd_);
    eotOffset_ += eventBytes;
}

}  // namespace sdfvj
