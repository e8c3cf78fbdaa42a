// libFuzzer target for input decoding: build with
//   cmake -S . -B build-fuzz -DSDFVJ_FUZZ=ON -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++
//   cmake --build build-fuzz --target fuzz_input && build-fuzz/src/control/fuzz_input -max_total_time=60
// (scripts/fuzz_input.sh does both). The first byte picks the decoder:
//   0: MIDI byte stream -> MidiDecoder -> ApplyEvent (a mapping that uses every source kind)
//   1: OSC packet -> a real lo_server (lo_server_dispatch_data: liblo's own bundle and message
//      parsing, as the live server thread does on each UDP datagram) -> the handler InputSession
//      registers (HandleOscMessage) -> EventQueue -> ApplyEvent
//   2: TOML mapping text -> ParseMapping -> ValidateMapping
#include <cstdint>
#include <cstdlib>

#include <lo/lo.h>

#include "control/control.h"

using namespace sdfvj;

namespace {

const char* kMapping = R"(
[[map]]
cc = 1
target = "a"
takeover = "pickup"
curve = "exponential"
[[map]]
cc14 = 2
target = "b"
takeover = "scale"
curve = "s"
[[map]]
cc = 16
encoder = "twos_complement"
target = "c"
[[map]]
nrpn = 300
target = "a"
curve = "logarithmic"
invert = true
[[map]]
pitchbend = true
target = "b"
range = [-100.0, 100.0]
[[map]]
program = "any"
[[pad]]
note = 36
action = "toggle"
target = "flag"
[[pad]]
note = 37
action = "effect"
effect = "fog"
[[pad]]
cc = 64
action = "tap_tempo"
[[map]]
osc = "/fader"
target = "c"
)";

struct World {
    Mapping mapping;
    std::vector<ParamDecl> decls = {{"a", ParamType::Float, 0.5f, 0.0f, 1.0f, "A"},
                                    {"b", ParamType::Float, 0.0f, -3.0f, 3.0f, "B"},
                                    {"c", ParamType::Int, 2.0f, 0.0f, 10.0f, "C"},
                                    {"flag", ParamType::Bool, 0.0f, 0.0f, 1.0f, "Flag"}};
    World() {
        if (!ParseMapping(kMapping, "fuzz.toml", &mapping).ok) std::abort();
    }
};

// The OSC side of InputSession without its thread: a UDP lo_server (its socket is never read)
// with the handler registered the way StartOsc registers it, fed through lo_server_dispatch_data.
struct OscServer {
    lo_server server = nullptr;
    EventQueue queue{1 << 12};
    InputCounters counters;
    OscServer() {
        server = lo_server_new_with_proto(nullptr, LO_UDP, &OnError);
        if (!server) std::abort();
        lo_server_add_method(server, nullptr, nullptr, &OnOsc, this);  // as InputSession::StartOsc
        lo_server_enable_queue(server, 0, 1);                            // likewise
    }
    static void OnError(int, const char*, const char*) {}
    static int OnOsc(const char* path, const char* types, lo_arg** argv, int argc, lo_message, void* user) {
        auto* o = static_cast<OscServer*>(user);
        std::string why;
        HandleOscMessage(path, types, reinterpret_cast<const void* const*>(argv), argc, 0.0, o->queue, o->counters, &why);
        return 0;
    }
};

void Check(const ParamState& p) {
    for (size_t i = 0; i < p.decls.size(); ++i) {
        const ParamDecl& d = p.decls[i];
        // The one invariant the renderer relies on: never a value outside the declared range.
        if (!(p.target[i] >= d.minValue && p.target[i] <= d.maxValue)) std::abort();
        if (!(p.value[i] >= d.minValue && p.value[i] <= d.maxValue)) std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static World w;
    if (size < 1) return 0;
    uint8_t mode = data[0] % 3;
    ++data;
    --size;
    ParamState p = MakeParamState(w.decls);
    MappingState ms;
    MappingActions acts;
    std::vector<ControlEvent> events;
    if (mode == 0) {
        MidiDecoder d;
        // Split the stream in two calls so running status across callbacks is exercised.
        size_t half = size / 2;
        DecodeMidiBytes(d, data, half, 0.0, &events);
        DecodeMidiBytes(d, data + half, size - half, 0.0, &events);
    } else if (mode == 1) {
        static OscServer osc;
        std::vector<uint8_t> packet(data, data + size);  // liblo takes a writable buffer
        if (!packet.empty()) lo_server_dispatch_data(osc.server, packet.data(), packet.size());
        events = osc.queue.DrainUntil(1e300);
    } else {
        Mapping m;
        std::string text(reinterpret_cast<const char*>(data), size);
        if (ParseMapping(text, "fuzz.toml", &m).ok) {
            std::string err;
            ValidateMapping(m, w.decls, &err);
            for (int v = 0; v < 128; v += 9) {
                ControlEvent e;
                e.midi[0] = uint8_t(0xB0 | (v & 15));
                e.midi[1] = uint8_t(v);
                e.midi[2] = uint8_t(127 - v);
                e.midiSize = 3;
                ApplyEvent(m, ms, e, p, &acts);
            }
            Check(p);
        }
        return 0;
    }
    for (const ControlEvent& e : events) {
        ApplyEvent(w.mapping, ms, e, p, &acts);
        StepSmoothing(p, 1.0 / 60.0);
    }
    Check(p);
    return 0;
}
