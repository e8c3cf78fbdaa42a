// libFuzzer entry for the SMF reader: any bytes must give ok or an error, never a crash, a
// sanitizer report or a runaway allocation. Run with scripts/fuzz_take.sh.
#include <cstdio>
#include <cstdlib>

#include "take/take.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    sdfvj::Take take;
    const sdfvj::TakeReadResult r = sdfvj::ParseTake(data, size, "fuzz.mid", &take);
    // Invariants the replay relies on.
    if (r.ok) {
        for (size_t i = 1; i < take.events.size(); ++i)
            if (!(take.events[i - 1].time <= take.events[i].time)) std::abort();
        for (const sdfvj::ControlEvent& e : take.events)
            if (e.source == sdfvj::EventSource::Midi && (e.midiSize == 0 || e.midiSize > 3)) std::abort();
        if (!take.events.empty() && !(take.duration >= take.events.back().time)) std::abort();
        // A round trip through our writer must read back.
        const std::vector<uint8_t> again = sdfvj::EncodeTake(take);
        sdfvj::Take back;
        if (!sdfvj::ParseTake(again.data(), again.size(), "again.mid", &back).ok) std::abort();
        if (back.events.size() != take.events.size()) std::abort();
    } else if (r.error.rfind("fuzz.mid: byte ", 0) != 0) {
        std::abort();
    }
    return 0;
}
