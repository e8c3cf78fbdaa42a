// kept_sizes.h - render targets of other sizes kept for a return to them (FrameRenderer::SetKeptSizes,
// IsfEffect::SetKeptSizes): on NVIDIA a new texture's first draw holds every context's frames for
// about 1 ms per MB, and `live`'s render scale moves between a few sizes (docs/performance.md,
// "Session 33").
#pragma once
#include <cstddef>
#include <vector>

namespace sdfvj {

// A size change: takes the target of size w x h (isFloat) out of `kept` (a default T when none),
// then keeps `left` (the size being left; w 0: none) at the back, letting the least recently left
// go (`release`) past `keep` targets, or releases it when none are kept. The size asked for is taken
// before the one left is stored, so a cycle through keep + 1 sizes finds each of them. T has w, h, isFloat.
template <class T, class Release>
T SwapKeptSize(std::vector<T>& kept, size_t keep, T left, int w, int h, bool isFloat, Release release) {
    T next{};
    for (auto it = kept.begin(); it != kept.end(); ++it)
        if (it->w == w && it->h == h && it->isFloat == isFloat) {
            next = *it;
            kept.erase(it);
            break;
        }
    if (left.w > 0 && keep > 0) {
        kept.push_back(left);
        if (kept.size() > keep) {
            release(kept.front());
            kept.erase(kept.begin());
        }
    } else if (left.w > 0) {
        release(left);
    }
    return next;
}

}  // namespace sdfvj
