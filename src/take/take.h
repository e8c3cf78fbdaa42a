// take: record and replay performances as Standard MIDI Files.
//
//   Take take;
//   TakeReadResult r = ReadTake("take.mid", &take);       // any SMF: format 0/1, tempo map, SMPTE
//   if (!r.ok) { fprintf(stderr, "%s\n", r.error.c_str()); }  // "take.mid: byte 812: ..."
//   for (auto& w : take.warnings) fprintf(stderr, "%s\n", w.c_str());  // read past, rest is sound
//
//   ReplayCursor cursor(take);                            // take must outlive the cursor
//   for (int frame = 0; !cursor.Done(); ++frame)
//       for (const ControlEvent& e : cursor.Until((frame + 1) / fps)) queue.Push(e);
//
//   TakeRecorder rec;                                     // live: sdfvj live --record take.mid
//   if (!rec.Open("take.mid", &error)) ...                 // a status line, the show goes on
//   rec.Record(e);                                        // any thread; never blocks on disk
//   rec.Close(clock.Now());                               // End-of-Track at the stop time
//
// File layout, the OSC payload and the crash-safety scheme are described in docs/takes.md.
// Depends on the standard library (and POSIX file calls) only, so it builds headless.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/control_event.h"
#include "core/durable_file.h"

namespace sdfvj {

// Resolution of the takes we write: 1000 ticks per quarter note at 120 BPM = 0.5 ms per tick.
constexpr int kTakeTicksPerQuarter = 1000;
constexpr int kTakeTempoMicroseconds = 500000;
constexpr double kTakeSecondsPerTick = 0.0005;

// A recorded (or DAW-drawn) performance: control events on a clock that starts at 0.
struct Take {
    std::vector<ControlEvent> events;   // sorted by time (seconds); equal times keep file order
    double duration = 0.0;              // seconds: the last End-of-Track or event, whichever is later
    std::vector<std::string> warnings;  // "take.mid: byte N: ..." for input that was read past
};

struct TakeReadResult {
    bool ok = false;
    std::string error;  // "take.mid: byte N: what is wrong" when !ok
};

// Reads a Standard MIDI File from disk (at most 64 MiB). `out` is replaced; on failure it holds
// no events, only the warnings collected before the error.
TakeReadResult ReadTake(const std::string& path, Take* out);

// Parses SMF bytes already in memory. `name` prefixes messages (usually the file name).
// Never crashes on any input; allocation is bounded by a small multiple of `size`.
TakeReadResult ParseTake(const uint8_t* data, size_t size, const std::string& name, Take* out);

// Encodes a take as an SMF format 0 file at kTakeSecondsPerTick resolution. Event times are
// rounded to the nearest tick; End-of-Track is at max(duration, last event).
std::vector<uint8_t> EncodeTake(const Take& take);
bool WriteTake(const std::string& path, const Take& take, std::string* error);

// Rounds seconds to the tick grid of the files we write (what a round trip gives back).
double QuantizeTakeTime(double seconds);

// Options for TakeRecorder::Open; zero-initialised means the defaults.
struct TakeRecorderDesc {
    double timeOrigin = 0.0;     // session time written as tick 0 (the clock at "record" press)
    double flushInterval = 0.0;  // seconds between background writes; 0 = 0.5 s
    std::string trackName;       // sequence name meta event; empty = "sdfvj take"
};

// Crash-safe recorder. Record() only appends to a memory buffer under a mutex; a writer
// thread appends the buffer to the file every flushInterval, re-writes End-of-Track and the
// MTrk length, and fdatasyncs, so the file on disk is always a readable SMF holding all but
// at most the last flushInterval (+ one write) of events, even after SIGKILL or power loss.
// Events are written in the order Record() is called; a time earlier than the previous
// event's is written at the previous event's tick (deltas are never negative).
class TakeRecorder {
public:
    TakeRecorder() = default;
    ~TakeRecorder();  // Close()s
    TakeRecorder(const TakeRecorder&) = delete;
    TakeRecorder& operator=(const TakeRecorder&) = delete;

    // Creates (truncates) `path` and writes an empty, valid SMF. False + *error on failure.
    bool Open(const std::string& path, std::string* error);
    bool Open(const std::string& path, const TakeRecorderDesc& desc, std::string* error);
    bool IsOpen() const { return open_.load(); }

    // Appends one event. MIDI channel messages and short system messages (clock, song
    // position...) and OSC messages are kept; an empty/invalid MIDI message is counted in
    // Dropped(). Thread-safe; cheap enough for the render thread or an input callback.
    void Record(const ControlEvent& e);

    // Writes everything recorded so far and syncs it to disk, now (blocking).
    void Flush();

    // Flushes, writes End-of-Track (at endTime when given, else at the last event) and closes.
    // Record() must not run concurrently with Close().
    void Close();
    void Close(double endTime);

    size_t Recorded() const { return recorded_.load(); }
    size_t Dropped() const { return dropped_.load(); }
    std::string Error() const;  // last I/O error ("take.mid: write failed: ..."), empty if none

private:
    void WritePending(int64_t endTick);  // endTick < 0: End-of-Track at the last event
    void SetError(const std::string& e);

    int fd_ = -1;
    std::string path_;
    TakeRecorderDesc desc_;

    mutable std::mutex pendingMutex_;  // guards pending_, lastTick_, error_
    std::vector<uint8_t> pending_;     // encoded events not yet on disk
    int64_t lastTick_ = 0;
    std::string error_;

    std::mutex io_;          // one writer of the file at a time
    uint64_t eotOffset_ = 0; // file offset of the End-of-Track event (overwritten next write)

    PeriodicFlush flusher_;  // WritePending(-1) every flushInterval

    std::atomic<bool> open_{false};  // Record() keeps events only while open
    std::atomic<size_t> recorded_{0};
    std::atomic<size_t> dropped_{0};
};

// Replays a take on any clock: each call hands out the events with time < t that were not
// handed out before, in order, each exactly once. Time never needs to move backwards; to
// start over, call Rewind(). Holds a reference: the take must outlive the cursor.
class ReplayCursor {
public:
    explicit ReplayCursor(const Take& take) : take_(&take) {}
    explicit ReplayCursor(Take&&) = delete;  // would dangle: keep the take alive elsewhere

    std::vector<ControlEvent> Until(double t);
    // Same, appending to *out (no allocation once *out has grown). Returns how many were added.
    size_t Until(double t, std::vector<ControlEvent>* out);

    bool Done() const { return next_ >= take_->events.size(); }
    // Time of the next event, or the take's duration when Done().
    double NextTime() const;
    void Rewind() { next_ = 0; }

private:
    const Take* take_;
    size_t next_ = 0;
};

}  // namespace sdfvj
