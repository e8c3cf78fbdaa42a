// render.glsl with the cheap branches: hard shadows, no AO, no specular, no fog, forward
// normals, fixed-step marching.
#define SHADOWS 1
#define AO 0
#define SPECULAR 0
#define PBR 0
#define REFLECTIONS 0
#define FOG 0
#define NORMALS 1
#define MARCH_FIXED 1
#define VARIANT_NAME "minimal"
#include "render_variant.inc"
