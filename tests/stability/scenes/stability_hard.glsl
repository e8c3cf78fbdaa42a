/*{
  "NAME": "stability_hard", "DESCRIPTION": "Test scene of the stability suite: one shape per case, with a parameter pushed to its limits.",
  "INPUTS": [
    {"NAME": "shape", "TYPE": "int", "DEFAULT": 1, "MIN": 0, "MAX": 9, "LABEL": "0 floor, 1 sphere+floor, 2 box, 3 torus, 4 poly smin, 5 exp smin, 6 cubic smin, 7 scaled box, 8 ellipsoid, 9 pow smin"},
    {"NAME": "k", "TYPE": "float", "DEFAULT": 0.5, "MIN": 0.0, "MAX": 1e30, "LABEL": "Operator parameter (blend radius, scale)"},
    {"NAME": "offset", "TYPE": "float", "DEFAULT": 0.0, "MIN": -1e6, "MAX": 1e6, "LABEL": "Shape centre z"},
    {"NAME": "radius", "TYPE": "float", "DEFAULT": 1.0, "MIN": 1e-3, "MAX": 1e5, "LABEL": "Sphere radius"}
  ],
  "EFFECTS": {"SHADOWS": "soft", "AO": true, "SPECULAR": true, "PBR": false, "REFLECTIONS": 0, "FOG": true},
  "CAMERA": {"POSITION": [0, 1, -5], "TARGET": [0, 1, 0], "FOV": 45},
  "LIGHT": {"DIRECTION": [0.6, 0.8, -0.4], "COLOR": [1, 0.96, 0.9]},
  "MATERIAL": {"ROUGHNESS": 0.4, "METALNESS": 0.0}
}*/
// stability_hard.glsl - shapes centred at (0, 1, u_offset) for the stability tests; each case
// has an analytic intersection or pushes one operator to the end of its range.
#include "lib/common.glsl"
#include "lib/primitives.glsl"
#include "lib/domain.glsl"
#include "lib/combinators.glsl"

vec4 map(vec3 p) {
    int shape = int(u_shape + 0.5f);
    vec3 q = pTranslate(p, vec3(0.0f, 1.0f, u_offset));
    float floorD = fPlane(p, vec3(0.0f, 1.0f, 0.0f), 0.0f);
    float sphere = fSphere(q, u_radius);
    float box = fBox(pTranslate(q, vec3(0.6f, 0.0f, 0.0f)), vec3(0.5f, 0.7f, 0.6f));
    float d = floorD;
    if (shape == 1) d = min(floorD, sphere);
    else if (shape == 2) d = fBox(q, vec3(1.0f, 0.6f, 0.8f));
    else if (shape == 3) d = fTorus(pRotateX(q, 0.5f * PI), 0.3f, 1.0f);
    else if (shape == 4) d = sminPoly(sphere, box, u_k);
    else if (shape == 5) d = sminExp(sphere, box, u_k);
    else if (shape == 6) d = sminCubic(sphere, box, u_k);
    else if (shape == 7) d = fOpScale(fBox(pScale(q, u_k), vec3(1.0f, 0.6f, 0.8f)), u_k);
    else if (shape == 8) d = fEllipsoid(q, vec3(1.0f, 0.5f, 0.25f) * u_radius);
    else if (shape == 9) d = sminPow(sphere, box, u_k);
    return vec4(0.7f, 0.6f, 0.5f, d);
}

float sceneLipschitz() { return 1.0f; }
