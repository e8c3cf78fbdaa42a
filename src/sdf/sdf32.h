// sdf32.h - the SDF library (shaders/lib, without shading.glsl which needs a scene's map)
// compiled as C++ in single precision: sdf32::fBox(sdf32::vec3(1.0f), ...).
#pragma once
#include "sdf/glsl_glm.h"

namespace sdf32 {
// Unnamed inner namespace: the GLSL functions are plain (non-inline) definitions, so
// give them internal linkage; any number of translation units may include this header.
namespace {
#define SDF_GLSL_DOUBLE 0
#include "sdf/glsl_prelude.h"
#include "lib/common.glsl"
#include "lib/primitives.glsl"
#include "lib/mandelbulb.glsl"
#include "lib/domain.glsl"
#include "lib/combinators.glsl"
#undef SDF_GLSL_DOUBLE
#undef uniform  // the prelude's `uniform` -> `static` must not leak out
}  // namespace
}  // namespace sdf32
