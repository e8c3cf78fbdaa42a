// The primitives scene compiled as C++ in float and double (see scene_instance.inc).
#include "accuracy/accuracy.h"

#define SCENE_FILE "scenes/primitives.glsl"
#define SCENE_INPUTS(X) X(smoothness) X(spin) X(bob) X(checker)
#define SCENE_DOUBLE 0
#define SCENE_NS acc_primitives32
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS acc_primitives64
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE

namespace sdfvj::accuracy {
CpuScene<float> MakeCpuScene32_primitives() { auto s = acc_primitives32::instance(); s.name = "primitives"; return s; }
CpuScene<double> MakeCpuScene64_primitives() { auto s = acc_primitives64::instance(); s.name = "primitives"; return s; }
}  // namespace sdfvj::accuracy
