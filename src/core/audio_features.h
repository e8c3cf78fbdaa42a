// AudioFeatures: what the audio analysis hands to the rest of sdfvj, once per frame.
//
// Audio never travels as samples past src/audio: the analysis turns the last frame's audio into
// these few numbers, and they travel as one ControlEvent (an OSC-shaped event on the address
// kAudioFeatureAddress), so the mapping (`audio = "bass"` entries), the take recorder and
// `render --replay` treat them like any other control:
//
//   ControlEvent e = AudioFeatureEvent(features, now);   // live: queue.Push(e) (the recorder keeps it)
//   AudioFeatures f;
//   if (ReadAudioFeatureEvent(e, &f)) ... f.Value(AudioFeature::Bass) ...   // mapping, replay
//
// Header only, standard library only: control (mapping), take and audio all read it.
#pragma once
#include <cstdint>
#include <string>

#include "core/control_event.h"

namespace sdfvj {

// The features a mapping entry can name (`audio = "bass"`). Every one is 0..1.
enum class AudioFeature { Level, Bass, Mid, High, Onset, Beat, Phase, Tempo, Count };

// The address of the per-frame feature event (it is recorded in takes like any OSC message).
inline constexpr const char* kAudioFeatureAddress = "/sdfvj/audio";

struct AudioFeatures {
    float level = 0.0f;      // RMS level of the frame's audio, dBFS mapped -60..0 -> 0..1
    float levelDb = -120.0f; // the same in dBFS (floor -120)
    float bass = 0.0f;       // 20-250 Hz, dBFS mapped -60..0 -> 0..1
    float mid = 0.0f;        // 250-4000 Hz
    float high = 0.0f;       // 4000 Hz and up
    bool onset = false;      // an onset (aubio) since the previous frame
    bool beat = false;       // a beat (aubio tempo tracker) since the previous frame
    float bpm = 0.0f;        // detected tempo; 0 = none yet
    float beatPhase = 0.0f;  // 0..1 from the last detected beat at bpm (0 while bpm is 0)
    // While the show records its audio (TAKE.wav, src/audio/wav.h): the WAV's sample count when
    // these features (and the spectrum on screen) were computed, so a replay reads the same
    // 1024 samples at this event's time. -1: not recording.
    int64_t wavSample = -1;

    // A feature as a control position 0..1 (Tempo: bpm 60..200 -> 0..1).
    float Value(AudioFeature f) const {
        switch (f) {
            case AudioFeature::Level: return level;
            case AudioFeature::Bass: return bass;
            case AudioFeature::Mid: return mid;
            case AudioFeature::High: return high;
            case AudioFeature::Onset: return onset ? 1.0f : 0.0f;
            case AudioFeature::Beat: return beat ? 1.0f : 0.0f;
            case AudioFeature::Phase: return beatPhase;
            case AudioFeature::Tempo: {
                float x = (bpm - 60.0f) / 140.0f;
                return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
            }
            case AudioFeature::Count: break;
        }
        return 0.0f;
    }
};

// Names as a mapping file writes them, in AudioFeature order.
inline const char* AudioFeatureName(AudioFeature f) {
    static const char* const kNames[] = {"level", "bass", "mid", "high", "onset", "beat", "phase", "tempo"};
    int i = int(f);
    return i >= 0 && i < int(AudioFeature::Count) ? kNames[i] : "?";
}
// "level, bass, ..." for error messages.
inline std::string AudioFeatureNameList() {
    std::string s;
    for (int i = 0; i < int(AudioFeature::Count); ++i) s += (i ? ", " : "") + std::string(AudioFeatureName(AudioFeature(i)));
    return s;
}
// False when `name` is not a feature.
inline bool ParseAudioFeatureName(const std::string& name, AudioFeature* out) {
    for (int i = 0; i < int(AudioFeature::Count); ++i)
        if (name == AudioFeatureName(AudioFeature(i))) {
            *out = AudioFeature(i);
            return true;
        }
    return false;
}

// The event layout: "/sdfvj/audio" with nine floats: level, levelDb, bass, mid, high, onset (0/1),
// beat (0/1), bpm, beatPhase; then, while the audio is recorded, an int32: wavSample. Floats
// survive a take round trip bit for bit.
inline ControlEvent AudioFeatureEvent(const AudioFeatures& f, double time) {
    ControlEvent e;
    e.time = time;
    e.source = EventSource::Osc;
    e.address = kAudioFeatureAddress;
    const float v[] = {f.level, f.levelDb, f.bass, f.mid, f.high, f.onset ? 1.0f : 0.0f, f.beat ? 1.0f : 0.0f,
                       f.bpm, f.beatPhase};
    for (float x : v) {
        OscArg a;
        a.type = 'f';
        a.f = x;
        e.args.push_back(a);
    }
    if (f.wavSample >= 0 && f.wavSample <= INT32_MAX) {
        OscArg a;
        a.type = 'i';
        a.i = int32_t(f.wavSample);
        e.args.push_back(a);
    }
    return e;
}

// False for any other event, or one of ours with fewer than nine float arguments.
inline bool ReadAudioFeatureEvent(const ControlEvent& e, AudioFeatures* out) {
    if (e.source != EventSource::Osc || e.address != kAudioFeatureAddress || e.args.size() < 9) return false;
    float v[9];
    for (int i = 0; i < 9; ++i) {
        if (e.args[size_t(i)].type != 'f') return false;
        v[i] = e.args[size_t(i)].f;
        if (!(v[i] == v[i])) v[i] = 0.0f;   // NaN from a damaged take reads as 0
    }
    out->level = v[0];
    out->levelDb = v[1];
    out->bass = v[2];
    out->mid = v[3];
    out->high = v[4];
    out->onset = v[5] >= 0.5f;
    out->beat = v[6] >= 0.5f;
    out->bpm = v[7];
    out->beatPhase = v[8];
    out->wavSample = e.args.size() > 9 && e.args[9].type == 'i' && e.args[9].i >= 0 ? e.args[9].i : -1;
    return true;
}

}  // namespace sdfvj
