// The mandelbulb scene compiled as C++ in float and double (see scene_instance.inc).
#include "accuracy/accuracy.h"

#define SCENE_FILE "scenes/mandelbulb.glsl"
#define SCENE_INPUTS(X) X(power) X(iterations) X(hue) X(colorSpread) X(spin)
#define SCENE_DOUBLE 0
#define SCENE_NS acc_mandelbulb32
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS acc_mandelbulb64
#include "accuracy/scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE

namespace sdfvj::accuracy {
CpuScene<float> MakeCpuScene32_mandelbulb() { auto s = acc_mandelbulb32::instance(); s.name = "mandelbulb"; return s; }
CpuScene<double> MakeCpuScene64_mandelbulb() { auto s = acc_mandelbulb64::instance(); s.name = "mandelbulb"; return s; }
}  // namespace sdfvj::accuracy
