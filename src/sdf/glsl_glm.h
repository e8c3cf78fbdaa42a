// glsl_glm.h - the global-scope half of the GLSL-as-C++ prelude: pulls in GLM and the
// standard headers once. Include it at global scope BEFORE opening a namespace that
// includes sdf/glsl_prelude.h (sdf32.h and sdf64.h do this for you).
#pragma once

// No GLM_FORCE_SWIZZLE on purpose: `p.xz` must fail to compile in C++, which keeps the
// shared shader code inside the subset that both languages accept.
#define GLM_FORCE_SILENT_WARNINGS
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <cmath>
