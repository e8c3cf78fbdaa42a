// The midi scene compiled as C++ in float and double (see scene_instance.inc).
#include "accuracy/accuracy.h"

#define SCENE_FILE "scenes/midi.glsl"
#define SCENE_INPUTS(X) X(scale) X(twist) X(displacement) X(smoothness) X(spin)
#define SCENE_DOUBLE 0
#define SCENE_NS acc_midi32
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS acc_midi64
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE

// The raw field with a global bound, as a plain raymarcher would march it.
#undef SCENE_GLOBAL_LIPSCHITZ
#define SCENE_GLOBAL_LIPSCHITZ 1
#define SCENE_DOUBLE 0
#define SCENE_NS acc_midi_global32
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS acc_midi_global64
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#undef SCENE_GLOBAL_LIPSCHITZ

namespace sdfvj::accuracy {
CpuScene<float> MakeCpuScene32_midi_global() { auto s = acc_midi_global32::instance(); s.name = "midi"; return s; }
CpuScene<double> MakeCpuScene64_midi_global() { auto s = acc_midi_global64::instance(); s.name = "midi"; return s; }
CpuScene<float> MakeCpuScene32_midi() { auto s = acc_midi32::instance(); s.name = "midi"; return s; }
CpuScene<double> MakeCpuScene64_midi() { auto s = acc_midi64::instance(); s.name = "midi"; return s; }
}  // namespace sdfvj::accuracy
