// GpuTimerRing: GPU time of draws without a sync, for the live overlay's graph and effect costs.
// Render thread only. Implemented in frame_renderer.cpp, next to FrameRenderer's own (syncing,
// benchmark-only) timer.
#pragma once
#include <cstdint>
#include <vector>

namespace sdfvj {

// Times draws with a small ring of GL_TIME_ELAPSED queries and never waits for the GPU: a result
// is read only once GL_QUERY_RESULT_AVAILABLE says so, a few frames after its draw. When every
// slot still waits, Begin() refuses (that frame goes untimed) instead of stalling. Results come
// back in submission order with the tag given to Begin(). Meaningless on llvmpipe
// (IsSoftwareRenderer()): callers say "n/a" there instead of showing its numbers.
//   if (ring.Begin(tag)) { ...draws...; ring.End(); }
//   for (const GpuTimerRing::Sample& s : ring.Poll()) graph.Add(s.ms);
// Queries are made on the first Begin() (a GL context must be current) and deleted with the ring.
class GpuTimerRing {
public:
    struct Sample { int tag = 0; double ms = 0.0; };
    explicit GpuTimerRing(int slots = 6) : slots_(slots < 1 ? 1 : slots) {}
    ~GpuTimerRing();
    GpuTimerRing(const GpuTimerRing&) = delete;
    GpuTimerRing& operator=(const GpuTimerRing&) = delete;
    // Opens a query; false (nothing timed) when all slots wait for results or one is open.
    bool Begin(int tag = 0);
    void End();
    // The results that are available now, oldest first. Never blocks.
    std::vector<Sample> Poll();
    int InFlight() const { return count_; }
    uint64_t Refused() const { return refused_; }    // Begin() calls turned down by a full ring
private:
    int slots_;
    std::vector<unsigned> ids_;
    std::vector<int> tags_;
    int head_ = 0, count_ = 0;     // oldest waiting slot, slots waiting (including an open one)
    bool open_ = false;
    uint64_t refused_ = 0;
};

}  // namespace sdfvj
