// control: MIDI and OSC in, mapped, smoothed parameter values out.
//
// The one header of the input layer. The data path it serves:
//
//   RtMidi callback ─┐                                   (render thread, once per frame)
//   liblo thread   ──┼─> EventQueue ─> DrainUntil(frameStart) ─> ApplyEvent ─> StepSmoothing(dt)
//   replay         ──┘
//
// Threading: input threads only decode and Push(); everything else in this header (ParamState,
// Mapping, MappingState, ApplyEvent) belongs to the render thread and takes no locks.
//
// Usage, per frame:
//   for (const ControlEvent& e : queue.DrainUntil(frameStart)) ApplyEvent(map, ms, e, params, &acts);
//   StepSmoothing(params, dt);
//   ... upload params.value[i] as u_<params.decls[i].name> ...
#pragma once
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/audio_features.h"
#include "core/control_event.h"
#include "core/param_decl.h"

namespace sdfvj {

// ---------------------------------------------------------------------------------------------
// The queue
// ---------------------------------------------------------------------------------------------

// Many producers (input threads), one consumer (render thread). Bounded: when full, the newest
// event is dropped and counted, so a flood can never grow memory or stall a frame.
class EventQueue {
public:
    explicit EventQueue(size_t capacity = 1 << 16) : capacity_(capacity) {}
    void Push(ControlEvent e);                               // any thread
    std::vector<ControlEvent> DrainUntil(double time);       // events with e.time <= time, in order
    size_t Dropped() const { return dropped_.load(); }       // events lost to a full queue
    size_t Pushed() const { return pushed_.load(); }         // events accepted so far
    size_t Size() const;

private:
    mutable std::mutex mutex_;
    std::deque<ControlEvent> events_;
    size_t capacity_;
    std::atomic<size_t> dropped_{0};
    std::atomic<size_t> pushed_{0};
};

// ---------------------------------------------------------------------------------------------
// Parameter values
// ---------------------------------------------------------------------------------------------

// One entry per ParamDecl, same order. `target` is where mapping writes; `value` follows it
// through a one-pole low-pass with time constant smoothingTau[i] (seconds, 0 = jump).
struct ParamState {
    std::vector<ParamDecl> decls;
    std::vector<float> value;
    std::vector<float> target;
    std::vector<float> smoothingTau;
    uint64_t clamped = 0;        // how many writes were out of range (and clamped)
    std::string lastClamp;       // one readable line about the latest clamp, for the overlay/log
};

ParamState MakeParamState(const std::vector<ParamDecl>& decls);   // value = target = default
int FindParam(const ParamState& s, const std::string& name);      // index or -1
// Exponential approach to target; depends only on dt, so replays give the same values.
void StepSmoothing(ParamState& s, double dt);
// Sets the target of `name` to `value` in the parameter's own units. Returns false and fills
// *error when the name is unknown or the value is not finite (nothing set), or when the value
// was out of range (the clamped value IS set and the clamp is counted in s.clamped).
bool SetParamByName(ParamState& s, const std::string& name, float value, std::string* error);
// Sets target index i, clamping; returns false (and records s.lastClamp) when it clamped.
bool SetParamTarget(ParamState& s, int index, float value);
// Valid parameter names, comma separated, for error messages.
std::string ParamNameList(const std::vector<ParamDecl>& decls);

// ---------------------------------------------------------------------------------------------
// Mapping (data, parsed from TOML) and its pure application
// ---------------------------------------------------------------------------------------------

enum class SourceKind { Cc, Note, PitchBend, Program, Nrpn, Osc, Audio };
enum class Curve { Linear, Exponential, Logarithmic, S };
enum class Takeover { None, Pickup, Scale };
enum class EncoderMode { Absolute, SignedBit, SignedBit2, BinaryOffset, TwosComplement };
// None: a continuous control (knob, fader). The others are pad behaviours.
enum class PadAction { None, Trigger, Toggle, Preset, Effect, TapTempo };

struct MappingEntry {
    SourceKind kind = SourceKind::Cc;
    int channel = 0;             // 1..16, 0 = any
    int number = 0;              // CC number, note, program (-1 = any), NRPN number (0..16383)
    std::string oscAddress;      // kind == Osc
    AudioFeature audio = AudioFeature::Level;  // kind == Audio: the feature (`audio = "bass"`)
    float gain = 1.0f;           // Audio: the feature is multiplied by this (then clamped to 0..1)
    float attack = 0.0f;         // Audio: seconds for a rise to reach 63% (0 = at once)
    float release = 0.0f;        // Audio: seconds for a fall to reach 63% (0 = at once)
    bool hiRes = false;          // CC: 14-bit pair, MSB on `number`, LSB on number+32; NRPN: 14-bit value
    std::string target;          // parameter name (continuous, trigger, toggle)
    int targetIndex = 0;         // target = N (1-based): the scene's Nth input, whatever its name
    bool hasRange = false;       // false: the parameter's declared range
    float outMin = 0.0f, outMax = 1.0f;
    Curve curve = Curve::Linear;
    float curveAmount = -1.0f;   // steepness; < 0 = default (3 for exponential/logarithmic, 2 for s)
    bool invert = false;         // control direction reversed (applied before the curve)
    float smoothing = -1.0f;     // seconds; < 0 keeps the parameter's current time constant
    Takeover takeover = Takeover::None;
    EncoderMode encoder = EncoderMode::Absolute;
    float step = 1.0f / 128.0f;  // relative encoders: fraction of the range per tick
    PadAction action = PadAction::None;
    std::string preset;          // action == Preset (empty: program number / note index)
    std::string effect;          // action == Effect
    int line = 0, column = 0;    // where the entry starts in its file, for messages
};

struct Mapping {
    std::string path;            // file it came from ("" when built in code)
    std::string name;            // [profile] name
    std::string device;          // [profile] device: port-name substring it is meant for
    std::vector<std::string> presets;   // [profile] presets: what preset pads 0, 1, 2... pick
    std::vector<MappingEntry> entries;
};

struct LoadResult {
    bool ok = false;
    std::string error;           // "file:line:col: what is wrong, expected ..."
};

// Parses a mapping file. On failure *out is left untouched (keep the last good mapping).
LoadResult LoadMapping(const std::string& path, Mapping* out);
LoadResult ParseMapping(const std::string& text, const std::string& path, Mapping* out);
// Every named target must be a declared parameter; an unknown one lists the valid names.
// Positional targets (target = N) always fit: past the scene's last input they do nothing.
// Returns false with one line per problem in *error.
bool ValidateMapping(const Mapping& m, const std::vector<ParamDecl>& decls, std::string* error);

// Per-entry and per-channel state that ApplyEvent keeps between events.
struct EntryState {
    float position = -1.0f;      // last known control position 0..1 (-1 = never seen)
    float lastWritten = 0.0f;    // value this entry last wrote to its target
    bool wroteOnce = false;
    bool engaged = false;        // takeover: control and parameter are in step
    int msb = -1;                // 14-bit CC: last MSB
    bool toggled = false;        // toggle pads
    float envelope = 0.0f;       // audio: the feature after attack/release
    double envelopeTime = -1.0;  // audio: time of the last feature event (-1 = none yet)
    bool audioHigh = false;      // audio pads: the feature was >= 0.5 at the last event
};
struct NrpnChannelState {
    int paramMsb = -1, paramLsb = -1;   // selected NRPN number (CC 99/98); -1 = none / RPN
    int valueMsb = 0;
};
struct MappingState {
    std::vector<EntryState> entries;              // resized by ApplyEvent to match the mapping
    std::array<NrpnChannelState, 16> nrpn{};
    std::map<std::string, bool> effects;          // effect on/off as the pads/OSC last set it
    uint64_t unmatched = 0;                       // events no mapping or address used
    uint64_t rejected = 0;                        // OSC messages with wrong types / unknown names
    std::string lastRejected;                     // one line about the latest rejection
};

// What an event asks of the world outside the parameters; the caller acts on it.
struct MappingActions {
    std::vector<std::string> presetSelect;        // preset names, or decimal indices
    std::vector<std::pair<std::string, bool>> effectToggles;  // effect, new state
    bool tapTempo = false;
    float detectedBpm = 0.0f;                     // tap_tempo from an audio beat: the analysis's tempo
                                                  // (0: none, use the taps' own tempo)
    std::vector<std::string> triggers;            // parameters a momentary pad pressed
    std::vector<std::string> messages;            // clamp/rejection reports, one line each
    void Clear() { *this = MappingActions{}; }
};

// The parameter an entry drives in `params`: by name, or the Nth input; -1 when there is none.
int TargetIndex(const MappingEntry& en, const ParamState& params);
// Pure: applies one event. Audio feature events (/sdfvj/audio, core/audio_features.h) drive the
// `audio = "feature"` entries: gain, then attack/release on the event times, then range and curve
// as for a knob; onset/beat pulses press pads (trigger, toggle, tap_tempo, preset, effect).
// Built-in OSC addresses (/sdfvj/param/<name> f 0..1,
// /sdfvj/raw/<name> f, /sdfvj/preset s|i, /sdfvj/effect/<name> i, /sdfvj/effects s LIST) work
// without any mapping; /sdfvj/clock is left to the show clock.
// `actions` may be null.
void ApplyEvent(const Mapping& m, MappingState& ms, const ControlEvent& e, ParamState& params,
                MappingActions* actions);

// The mapping's transfer function pieces, exposed for tests and for MIDI learn.
float ApplyCurve(Curve c, float x, float amount);          // 0..1 -> 0..1, monotonic
float InverseCurve(Curve c, float y, float amount);
int DecodeRelative(EncoderMode mode, int value7);           // ticks, signed

// ---------------------------------------------------------------------------------------------
// Decoding (input threads; fuzzed)
// ---------------------------------------------------------------------------------------------

// Byte stream -> complete short messages. Resolves running status, skips SysEx, realtime and
// system-common bytes, counts data bytes that have no status to belong to.
struct MidiDecoder {
    uint8_t status = 0;          // running status (0 = none)
    uint8_t data[2] = {0, 0};
    int have = 0;
    int skip = 0;                // data bytes of a system-common message still to skip
    bool inSysex = false;
    uint64_t stray = 0;          // data bytes without a status
    uint64_t ignored = 0;        // SysEx, clock, active sensing, system common
    uint64_t messages = 0;
    // MIDI Time Code (control/mtc.h): a quarter frame (F1 dd) becomes a 2-byte event, a full-frame
    // SysEx an event made by MtcFullFrameEvent; other SysEx stays ignored.
    bool quarterFrame = false;   // the data byte being skipped is a quarter frame's
    uint8_t sysex[10] = {};
    int sysexSize = 0;           // -1: longer than a full frame
};
void DecodeMidiBytes(MidiDecoder& d, const uint8_t* bytes, size_t size, double time,
                     std::vector<ControlEvent>* out);

// OSC message (already split by liblo) -> event. Returns false for messages sdfvj cannot use
// (a /sdfvj/ address with wrong argument types); *why says what was wrong.
bool DecodeOscMessage(const char* path, const char* types, const void* const* argv, int argc,
                      double time, ControlEvent* out, std::string* why);
// /sdfvj/clock iii[sf...]: a `--forward` leader's frame (docs/sync.md): its show time as whole
// SECONDS (0..kLeaderClockMaxSeconds) and MICROSECONDS (0..999999), RUNNING 1 or stopped 0, then
// the values that frame rendered as NAME VALUE pairs (at most 256; names 1..64 bytes, finite
// float or int values). Anything else is false with *why ("/sdfvj/clock: ..., expected ...").
constexpr int32_t kLeaderClockMaxSeconds = 10000000;   // 115 days
// The tempo pairs a leader appends ('@' starts no parameter name): u_beat's phase and u_bpm.
constexpr const char* kLeaderBeatName = "@beat";
constexpr const char* kLeaderBpmName = "@bpm";
struct LeaderClock {
    double seconds = 0.0;
    bool running = true;
    std::vector<std::pair<std::string, float>> values;
};
bool ParseLeaderClock(const std::vector<OscArg>& args, LeaderClock* out, std::string* why);
struct InputCounters;
// The body of InputSession's liblo method handler: decode, count, queue. The fuzzer runs it
// behind a real lo_server, so it fuzzes exactly what production runs. False, with *why, for a
// message sdfvj cannot use.
bool HandleOscMessage(const char* path, const char* types, const void* const* argv, int argc, double time,
                      EventQueue& queue, InputCounters& counters, std::string* why);
// Raw OSC packet bytes -> events (liblo's deserialiser, then DecodeOscMessage). Counts.
struct OscDecodeCounts { uint64_t malformed = 0, wrongType = 0, ok = 0; };
void DecodeOscPacket(const uint8_t* data, size_t size, double time, std::vector<ControlEvent>* out,
                     OscDecodeCounts* counts);

// ---------------------------------------------------------------------------------------------
// Devices
// ---------------------------------------------------------------------------------------------

struct InputOptions {
    std::string midiPort;                   // name substring or index; empty = every input port
    bool midi = true;                       // false: no MIDI at all
    bool virtualPort = true;                // also open a virtual input port for other software
    std::string virtualPortName = "sdfvj";
    int oscPort = 9000;                     // 0 = let the system pick a free port; -1 = no OSC
    std::string oscFeedback;                // "HOST:PORT"; empty = no feedback
    double logInterval = 1.0;               // seconds between "bad input" log lines
    bool log = true;                        // print status changes and bad-input counts on stderr
};

// Counters the input threads bump; read them from any thread.
struct InputCounters {
    std::atomic<uint64_t> midiMessages{0}, midiStray{0}, midiIgnored{0};
    std::atomic<uint64_t> oscMessages{0}, oscMalformed{0}, oscWrongType{0};
};

// Owns the MIDI ports, the OSC server thread and a watcher thread that reconnects MIDI ports
// (every 250 ms) and writes the rate-limited bad-input log. A device that cannot be opened is a
// status line, never an exception.
class InputSession {
public:
    InputSession(const InputOptions& opt, EventQueue& queue, std::function<double()> clock);
    ~InputSession();
    InputSession(const InputSession&) = delete;
    InputSession& operator=(const InputSession&) = delete;

    std::vector<std::string> StatusLines() const;    // one per device / problem
    int OscPort() const;                             // bound UDP port, or -1
    void Poll();                                     // reconnect check; the watcher calls it too
    std::vector<std::string> OpenMidiPorts() const;  // names of the ports being listened to
    const InputCounters& Counters() const;
    // Sends every parameter as /sdfvj/param/<name> f (0..1) and /sdfvj/preset s to the
    // --osc-feedback target. Call from the render thread after a preset change.
    void SendFeedback(const ParamState& params, const std::string& presetName);

    struct Impl;
private:
    std::unique_ptr<Impl> impl_;
};

// MIDI learn, shared by `sdfvj learn` and learn in the live overlay.
struct LearnState {
    std::map<int, int> ccFirst;        // first value seen per channel*128+cc ("moves" = a second value)
    std::map<int, int> nrpnSelected;   // NRPN number selected per channel (CC 99/98)
};
// The TOML source lines of the control an event shows moving ("cc = 2\nchannel = 1"), or "".
// A CC moves when it sends a second, different value; a note-on becomes a toggle pad; NRPN waits
// for its number; /sdfvj/ addresses and addresses that cannot sit in a TOML string are not learned.
std::string LearnSource(const ControlEvent& e, LearnState& state);
// Appends a [[map]] for `param` with `source` to the mapping file, all or nothing: the new text
// must parse, add exactly that entry and (when `decls` is not empty) fit the scene; it is written
// atomically. Returns "" or one `file:line:col: ...` line; on failure the file is unchanged.
std::string AddLearnedEntry(const std::string& mappingPath, const std::string& param, const std::string& source,
                            const std::vector<ParamDecl>& decls, const std::string& comment);
// Writes `text` to a temporary file next to `path` and renames it over `path`: a reader (a
// running `live` reloading the file) sees the old file or the new one, never a mix.
bool WriteFileAtomically(const std::string& path, const std::string& text, std::string* error);

// "index: name" for every MIDI input port on the active API (JACK when a server runs, else ALSA).
std::vector<std::string> ListMidiPorts();
// `sdfvj learn --param NAME`: waits for the next control that moves and appends a mapping
// entry for it to mappingPath. Returns 0 on success, 1 on timeout, 2 on a file problem.
int RunLearn(const std::string& param, const std::string& mappingPath, double timeoutSeconds);
// `sdfvj bench input`: event-to-frame latency and a 10,000 msg/s flood; prints medians.
int RunInputBench(double seconds);

}  // namespace sdfvj
