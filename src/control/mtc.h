// MIDI Time Code (MTC): what a show-control master (QLab, a DAW, a timecode generator) sends so
// that followers run on its clock. Pure code: bytes in, timecode and a show clock out; no device.
//
//   MtcReader reader;                              // one per input
//   MtcSync sync;                                  // the show clock that follows the master
//   Timecode tc;
//   double at;
//   MtcOnQuarterFrame(sync, now);                  // F1 dd: 8 of them carry one time (2 frames)
//   if (MtcQuarterFrame(reader, data, &tc, &at)) MtcOnTimecode(sync, at, tc.rate, now, false, reader.direction);
//   if (ParseMtcFullFrame(sysex, n, &tc))          // F0 7F dev 01 01 hh mm ss ff F7: a locate
//       MtcOnTimecode(sync, TimecodeSeconds(tc), tc.rate, now, true);
//   MtcTick(sync, now);                            // each frame: lost master -> freewheel, then stop
//   double showTime = MtcShowTime(sync, now);
//
// The show clock is the master's time, advanced between quarter frames by the local clock. A
// time that disagrees with the running clock by more than MtcSync::seekFrames frames is a jump
// (the master located): the clock seeks. A full-frame message is a locate: the clock holds there
// until quarter frames run again. No quarter frame for lostSeconds (0.25 s): the master is lost
// and the clock freewheels at speed 1, said once; after freewheelSeconds more it stops.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/control_event.h"

namespace sdfvj {

// The four MTC rates, numbered as on the wire (the two "rate" bits).
enum class MtcRate : uint8_t { Fps24 = 0, Fps25 = 1, Fps2997Drop = 2, Fps30 = 3 };
double MtcFramesPerSecond(MtcRate rate);   // 24, 25, 29.97 (30000/1001), 30
const char* MtcRateName(MtcRate rate);     // "24", "25", "29.97df", "30"

struct Timecode {
    int hours = 0, minutes = 0, seconds = 0, frames = 0;   // frames < the rate's nominal fps
    MtcRate rate = MtcRate::Fps25;
};
bool operator==(const Timecode& a, const Timecode& b);
// Seconds since 00:00:00:00; drop-frame labels (29.97df) are counted as SMPTE drops them.
double TimecodeSeconds(const Timecode& tc);
// The label of the frame that runs at `seconds` (floor), for senders and tests.
Timecode TimecodeAt(double seconds, MtcRate rate);
// "01:02:03:04@25"
std::string FormatTimecode(const Timecode& tc);

// Encoders (a test client, `--forward` followers): 8 quarter-frame messages "F1 dd" (16 bytes,
// pieces 0..7, or 7..0 when `reverse`) and the 10-byte full-frame SysEx.
std::vector<uint8_t> MtcQuarterFrames(const Timecode& tc, bool reverse = false);
std::vector<uint8_t> MtcFullFrame(const Timecode& tc, uint8_t device = 0x7F);

// F0 7F <device> 01 01 hh mm ss ff F7 -> timecode; false for anything else (or out of range).
bool ParseMtcFullFrame(const uint8_t* bytes, size_t size, Timecode* out);

// MTC as ControlEvents (the decoder makes them; mapping and tempo ignore them): a quarter
// frame is the 2-byte MIDI event F1 dd; a full frame (SysEx, too long for midi[]) is a MIDI event
// F0 7F 01 with its four data bytes (hh with the rate bits, mm, ss, ff) as 'i' arguments.
ControlEvent MtcFullFrameEvent(const Timecode& tc, double time);
enum class MtcEventKind { None, QuarterFrame, FullFrame };
// What `e` is: a quarter frame (*data = its data byte) or a full frame (*tc), else None.
MtcEventKind MtcEventOf(const ControlEvent& e, uint8_t* data, Timecode* tc);

// Assembles quarter frames. Forward, pieces arrive 0..7 and the time is whole when piece 7
// arrives; the pieces hold the label of piece 0's frame, and piece 7 is sent 1 3/4 frames
// later: the result is that moment (label + 1.75 frames, as seconds in MtcTime). Backwards
// (pieces 7..0) it is whole at piece 0 and the result is the label as sent. A piece out of
// sequence starts over (counted).
struct MtcReader {
    uint8_t nibble[8] = {};
    int next = -1;          // the piece expected next; -1: waiting for piece 0 or 7
    int have = 0;           // pieces in a row
    int direction = 0;      // +1 forward, -1 backward, 0 not known yet
    uint64_t quarterFrames = 0, timecodes = 0, outOfSequence = 0;
};
// One quarter-frame data byte (the byte after F1). True when a time is whole: *out is the label
// the pieces carry, *seconds the master's time as the last piece arrived (see above).
bool MtcQuarterFrame(MtcReader& r, uint8_t data, Timecode* out, double* seconds = nullptr);

struct MtcSync {
    // Settings (zero = the default noted).
    double seekFrames = 0;        // a jump larger than this seeks; default 2 frames
    double lostSeconds = 0;       // no quarter frame this long: freewheel; default 0.25 s
    double freewheelSeconds = 0;  // freewheel this long, then stop; default 2 s
    // Another master than MTC (the `--forward` leader's /sdfvj/clock): its name and what it
    // sends, for the lines said ("leader", "/sdfvj/clock"); times are then said in seconds.
    std::string name, pulse;

    // State.
    enum class State { Waiting, Locked, Holding, Freewheel, Stopped };
    State state = State::Waiting;
    double anchorShow = 0.0;      // show time at anchorLocal
    double anchorLocal = 0.0;     // local clock when the master last said where it is
    double lastQuarter = -1.0;    // local time of the last quarter frame
    int direction = 1;            // the master runs forward (+1) or backwards (-1)
    double fps = 25.0;
    MtcRate rate = MtcRate::Fps25;
    uint64_t seeks = 0;
    std::vector<std::string> pending;   // lines to say once (lost, stopped, locked again, seek)
};
// The master said where it is (`seconds` of timecode, at `rate`): `fullFrame` = a locate (hold
// there), else a running quarter-frame time, `direction` as the reader saw it.
void MtcOnTimecode(MtcSync& s, double seconds, MtcRate rate, double localTime, bool fullFrame, int direction = 1);
// Every quarter frame (whole time or not): the master is alive.
void MtcOnQuarterFrame(MtcSync& s, double localTime);
// Once a frame: notices a lost master (Freewheel, then Stopped).
void MtcTick(MtcSync& s, double localTime);
// The show clock now.
double MtcShowTime(const MtcSync& s, double localTime);
// How far a time may be from the running clock before it is a jump (seekFrames frames).
double MtcSeekSeconds(const MtcSync& s);
// "MTC 00:01:02:03@25 locked" / "... lost: freewheeling" / "... stopped" / "MTC: waiting for the master".
std::string MtcStatusLine(const MtcSync& s, double localTime);

}  // namespace sdfvj
