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
  "EFFECTS": {"SHADOWS": "soft", "AO": true, "SPECULAR": true, "PBR": false, "REFLECTIONS": 0, "FOG": true, "NORMALS": "forward"},
  "CAMERA": {"POSITION": [0, 3.6, -8.2], "TARGET": [0, 0.2, 0.6], "FOV": 48},
  "LIGHT": {"DIRECTION": [0.45, 0.85, -0.3], "COLOR": [1, 0.96, 0.9]},
  "MATERIAL": {"ROUGHNESS": 0.35, "METALNESS": 0.0}
}*/
// field50.glsl - 50 shapes (10 x 5 cells of lib/field.glsl: spheres, rounded boxes, tori and
// capsules) blended into their neighbours (u_blend) and into the floor (u_floorBlend), lifted
// by a wave rolling across the field (u_wave high, u_speed fast) and spinning (u_spin),
// u_size scales them. Each map() evaluates 4 shapes whatever the count: see lib/field.glsl
// for why that is exact within the blend radius.
const float FIELD_NX = 10.0f;
const float FIELD_NZ = 5.0f;

#include "lib/field_scene.glsl"
