// render.glsl with every effect on: improved soft shadows, AO, PBR, 2 reflection bounces,
// fog, tetrahedron normals.
#define SHADOWS 3
#define AO 1
#define SPECULAR 1
#define PBR 1
#define REFLECTIONS 2
#define FOG 1
#define NORMALS 2
#define VARIANT_NAME "full"
#include "render_variant.inc"
