// The character scene compiled as C++ in float and double (see scene_instance.inc).
#include "accuracy/accuracy.h"

#define SCENE_FILE "scenes/character.glsl"
#define SCENE_INPUTS(X) X(speed) X(wave) X(blend) X(floorBlend)
#define SCENE_DOUBLE 0
#define SCENE_NS acc_character32
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS acc_character64
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE

namespace sdfvj::accuracy {
CpuScene<float> MakeCpuScene32_character() { auto s = acc_character32::instance(); s.name = "character"; return s; }
CpuScene<double> MakeCpuScene64_character() { auto s = acc_character64::instance(); s.name = "character"; return s; }
}  // namespace sdfvj::accuracy
