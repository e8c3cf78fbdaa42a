/*{
  "NAME": "field50", "DESCRIPTION": "Fifty shapes on a 10x5 grid (spheres, rounded boxes, tori, capsules) melting into their neighbours and the floor under a rolling wave; evaluation looks at 4 shapes whatever the count.",
  "INPUTS": [
    {"NAME": "blend", "TYPE": "float", "DEFAULT": 0.3, "MIN": 0.0, "MAX": 0.35, "LABEL": "Blend"},
    {"NAME": "size", "TYPE": "float", "DEFAULT": 0.95, "MIN": 0.3, "MAX": 1.0, "LABEL": "Size"},
    {"NAME": "wave", "TYPE": "float", "DEFAULT": 0.5, "MIN": 0.0, "MAX": 1.5, "LABEL": "Wave height"},
    {"NAME": "speed", "TYPE": "float", "DEFAULT": 1.0, "MIN": 0.0, "MAX": 4.0, "LABEL": "Wave speed"},
    {"NAME": "spin", "TYPE": "float", "DEFAULT": 0.6, "MIN": 0.0, "MAX": 3.0, "LABEL": "Spin speed"},
    {"NAME": "floorBlend", "TYPE": "float", "DEFAULT": 0.1, "MIN": 0.0, "MAX": 0.3, "LABEL": "Floor blend"}
  ],
  "EFFECTS": {"SHADOWS": "soft", "AO": true, "SPECULAR": true, "PBR": false, "REFLECTIONS": 0, "FOG": true},
  "CAMERA": {"POSITION": [0, 3.6, -8.2], "TARGET": [0, 0.2, 0.6], "FOV": 48},
  "LIGHT": {"DIRECTION": [0.45, 0.85, -0.3], "COLOR": [1, 0.96, 0.9]},
  "MATERIAL": {"ROUGHNESS": 0.35, "METALNESS": 0.0}
}*/
// field50.glsl - 50 shapes (10 x 5 cells of lib/field.glsl: spheres, rounded boxes, tori and
// capsules) blended into their neighbours (u_blend) and into the floor (u_floorBlend), lifted
// by a wave rolling across the field (u_wave high, u_speed fast) and spinning (u_spin),
// u_size scales them. Each map() evaluates 4 shapes whatever the count: see lib/field.glsl
// for why that is exact within the blend radius.
#include "lib/common.glsl"
#include "lib/field.glsl"

const float FIELD_NX = 10.0f;
const float FIELD_NZ = 5.0f;

// Bounding volume for the renderer (render.glsl BOUNDS): the shapes and the floor apart.
#define SCENE_BOUND 1
#define SCENE_GROUND 1

// The floor y = 0, a dark grid under the shapes.
vec4 mapGround(vec3 p) {
    float grid = max(smoothstep(0.47f, 0.5f, abs(fract(p.x) - 0.5f)), smoothstep(0.47f, 0.5f, abs(fract(p.z) - 0.5f)));
    return vec4(mix(vec3(0.16f), vec3(0.10f), grid), p.y);
}

vec4 map(vec3 p) {
    vec4 shapes = fieldMap(p, FIELD_NX, FIELD_NZ, u_size, u_blend, u_wave, u_time * u_speed * 2.0f, u_time * u_spin);
    return fOpUnionSmoothColor(mapGround(p), shapes, u_floorBlend);
}

// A sphere around every shape; past it plus the floor blend the smooth union leaves the floor
// exact (the renderer's contract for SCENE_GROUND). The blend lowers the shapes' field by at
// most blend / 4, which the sphere's extra covers too.
vec4 sceneBound() { return fieldBound(FIELD_NX, FIELD_NZ, u_size, u_wave, 0.25f * max(u_blend, 0.0f) + max(u_floorBlend, 0.0f) + 0.02f); }

// Exact shapes, rotations, the two-nearest polynomial blend, the continuous cut-off and the
// floor's smooth union all keep |grad| <= 1 (lib/field.glsl).
float sceneLipschitz() { return 1.0f; }
