// sdf64.h - the SDF library compiled as C++ in double precision (the reference): every
// `float` in the shared code becomes `double`, vec3 is glm::dvec3.
#pragma once
#include "sdf/glsl_glm.h"

namespace sdf64 {
// Unnamed inner namespace: the GLSL functions are plain (non-inline) definitions, so
// give them internal linkage; any number of translation units may include this header.
namespace {
#define SDF_GLSL_DOUBLE 1
#include "sdf/glsl_prelude.h"
#define float double
#include "lib/common.glsl"
#include "lib/primitives.glsl"
#include "lib/mandelbulb.glsl"
#include "lib/domain.glsl"
#include "lib/combinators.glsl"
#undef float
#undef SDF_GLSL_DOUBLE
#undef uniform  // the prelude's `uniform` -> `static` must not leak out
}  // namespace
}  // namespace sdf64
