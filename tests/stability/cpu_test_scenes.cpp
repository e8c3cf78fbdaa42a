// The stability suite's own scenes compiled as C++ (float and double).
#include "stability_util.h"

#define SCENE_FILE "stability_hard.glsl"
#define SCENE_INPUTS(X) X(shape) X(k) X(offset) X(radius)
#define SCENE_DOUBLE 0
#define SCENE_NS stab_hard32
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS stab_hard64
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#undef SCENE_INPUTS
#undef SCENE_FILE

#define SCENE_FILE "stability_bulb.glsl"
#define SCENE_INPUTS(X) X(power) X(iterations)
#define SCENE_DOUBLE 0
#define SCENE_NS stab_bulb32
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS stab_bulb64
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#undef SCENE_INPUTS
#undef SCENE_FILE

namespace stability {
sdfvj::accuracy::CpuScene<float> Hard32() { return stab_hard32::instance(); }
sdfvj::accuracy::CpuScene<double> Hard64() { return stab_hard64::instance(); }
sdfvj::accuracy::CpuScene<float> Bulb32() { return stab_bulb32::instance(); }
sdfvj::accuracy::CpuScene<double> Bulb64() { return stab_bulb64::instance(); }
}  // namespace stability
