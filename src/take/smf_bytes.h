// Internal to src/take: byte-level helpers shared by the SMF reader and writer, and the
// encoding of OSC messages inside sequencer-specific meta events (see docs/takes.md).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/control_event.h"

namespace sdfvj::smf {

// Prefix of our sequencer-specific (FF 7F) payloads: the non-commercial manufacturer ID,
// then "OSC" and a payload version. Anything else in FF 7F belongs to someone else.
inline constexpr uint8_t kOscPrefix[5] = {0x7D, 'O', 'S', 'C', 0x01};

inline constexpr uint32_t kMaxVlq = 0x0FFFFFFF;  // 4 bytes of 7 bits

void PutU16(std::vector<uint8_t>* out, uint32_t v);
void PutU32(std::vector<uint8_t>* out, uint32_t v);
void PutVlq(std::vector<uint8_t>* out, uint32_t v);  // v <= kMaxVlq

// The "MThd" chunk of a format 0, one-track file at our resolution, and the start of the
// track (tempo + sequence name) that follows the "MTrk" header.
std::vector<uint8_t> HeaderChunk();
std::vector<uint8_t> TrackPrologue(const std::string& trackName);

// Appends one event with its delta time. Returns false (nothing appended) when the event has
// no SMF form (empty or malformed MIDI message). Deltas above kMaxVlq are carried by empty
// text events first.
bool PutEvent(std::vector<uint8_t>* out, int64_t deltaTicks, const ControlEvent& e);
void PutEndOfTrack(std::vector<uint8_t>* out, int64_t deltaTicks);

// Seconds -> ticks at our resolution (rounded, >= 0).
int64_t SecondsToTicks(double seconds);

// OSC message <-> FF 7F payload. Decode returns false with *why set when the payload is ours
// but malformed; the arguments decoded before the fault are kept in *e.
void EncodeOscPayload(const ControlEvent& e, std::vector<uint8_t>* payload);
bool IsOscPayload(const uint8_t* p, size_t n);
bool DecodeOscPayload(const uint8_t* p, size_t n, ControlEvent* e, std::string* why);

}  // namespace sdfvj::smf
