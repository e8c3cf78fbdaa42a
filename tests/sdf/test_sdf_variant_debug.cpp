// render.glsl's debug views compile as C++ (the step heatmap; depth and normals share the
// same #if chain and are covered by scripts/check_glsl.sh).
#define SHADOWS 0
#define DEBUG_VIEW 1
#define VARIANT_NAME "debug-steps"
#include "render_variant.inc"
