/*{
  "NAME": "midi", "DESCRIPTION": "Five primitives melted together by a smooth union; knobs scale, twist, displace and soften them (the MIDI scale/twist scenes). The top of each range is a stress case for the marcher.",
  "INPUTS": [
    {"NAME": "scale", "TYPE": "float", "DEFAULT": 1.0, "MIN": 0.25, "MAX": 2.0, "LABEL": "Scale"},
    {"NAME": "twist", "TYPE": "float", "DEFAULT": 0.5, "MIN": -3.0, "MAX": 3.0, "LABEL": "Twist"},
    {"NAME": "displacement", "TYPE": "float", "DEFAULT": 0.04, "MIN": 0.0, "MAX": 0.25, "LABEL": "Displacement"},
    {"NAME": "smoothness", "TYPE": "float", "DEFAULT": 0.35, "MIN": 0.0, "MAX": 1.0, "LABEL": "Smoothness"},
    {"NAME": "spin", "TYPE": "float", "DEFAULT": 0.3, "MIN": 0.0, "MAX": 2.0, "LABEL": "Spin speed"}
  ],
  "EFFECTS": {"SHADOWS": "soft", "AO": true, "SPECULAR": true, "PBR": false, "REFLECTIONS": 0, "FOG": true, "NORMALS": "forward"},
  "CAMERA": {"POSITION": [0, 2, -6], "TARGET": [0, 1.1, 0], "FOV": 45},
  "LIGHT": {"DIRECTION": [0.6, 0.8, -0.4], "COLOR": [1, 0.96, 0.9]},
  "MATERIAL": {"ROUGHNESS": 0.35, "METALNESS": 0.0}
}*/
// midi.glsl - sphere, box, torus, capsule and hexagonal prism blended by a smooth union,
// then scaled (u_scale), twisted around Y (u_twist, radians per unit), displaced by a
// sine pattern (u_displacement, amplitude) and blended (u_smoothness, blend radius).
// The twist and displacement break the distance property; sceneLipschitz() reports the
// gradient bound for the current knob values so the marcher never oversteps.
#include "lib/common.glsl"
#include "lib/primitives.glsl"
#include "lib/domain.glsl"
#include "lib/combinators.glsl"

// SCENE_GLOBAL_LIPSCHITZ 1: raw field + global bound (the stability tests and the accuracy
// bench's "plain" row use it to show what the local correction buys).
#ifndef SCENE_GLOBAL_LIPSCHITZ
#define SCENE_GLOBAL_LIPSCHITZ 0
#endif

const float MIDI_RADIUS = 1.45f;         // the primitives lie within this distance of the blob's origin (unscaled)
const float MIDI_DISPLACE_FREQ = 6.0f;   // spatial frequency of the displacement

// The unscaled, untwisted blob around the origin.
vec4 midiBlob(vec3 q) {
    float k = u_smoothness;
    float pulse = 0.06f * sin(TAU * u_beat);
    vec4 res = vec4(0.95f, 0.30f, 0.12f, fSphere(pTranslate(q, vec3(0.0f, 0.55f, 0.0f)), 0.5f + pulse));
    res = fOpUnionSmoothColor(res, vec4(0.15f, 0.45f, 0.95f, fRoundBox(pTranslate(q, vec3(0.75f, -0.1f, 0.0f)), vec3(0.4f), 0.05f)), k);
    res = fOpUnionSmoothColor(res, vec4(0.95f, 0.80f, 0.15f, fTorus(pRotateZ(pTranslate(q, vec3(-0.8f, -0.1f, 0.0f)), 0.5f * PI), 0.14f, 0.42f)), k);
    res = fOpUnionSmoothColor(res, vec4(0.20f, 0.80f, 0.40f, fCapsule(q, vec3(0.0f, -0.75f, 0.55f), vec3(0.0f, -0.2f, 0.7f), 0.2f)), k);
    res = fOpUnionSmoothColor(res, vec4(0.75f, 0.25f, 0.85f, fHexPrism(pTranslate(q, vec3(0.0f, -0.45f, -0.6f)), vec2(0.3f, 0.3f))), k);
    return res;
}

// Gradient bound of the blob for the current knobs. Twist: shear k*R at the blob's radius;
// displacement adds amplitude * frequency. The scale multiplies the distance back, so it leaves
// the bound unchanged.
float midiBlobLipschitz() {
    return lipschitzTwist(u_twist, MIDI_RADIUS) +
           lipschitzDisplacement(u_displacement, MIDI_DISPLACE_FREQ);
}

// Bounding volume for the renderer (render.glsl BOUNDS): the blob and the ground apart.
#define SCENE_BOUND 1
#define SCENE_GROUND 1

// The checkered ground plane y = 0.
vec4 mapGround(vec3 p) {
    float checker = mod(floor(p.x) + floor(p.z), 2.0f);
    return vec4(vec3(0.26f + 0.08f * checker), p.y);
}

// Where the blob's centre sits for the current scale.
vec3 midiCentre() { return vec3(0.0f, 0.15f + 1.0f * u_scale, 0.0f); }

// A sphere holding the blob for every knob position: the unscaled primitives lie within
// MIDI_RADIUS of the blob's origin; the chain of four smooth unions can lower the field by up
// to the blend radius in all, the displacement by its amplitude; the twist and the spin rotate
// about an axis through the origin, so they keep it; the scale scales it.
vec4 sceneBound() {
    vec3 c = midiCentre();
    float r = MIDI_RADIUS + max(u_smoothness, 0.0f) + abs(u_displacement) + 0.02f;
    return vec4(c.x, c.y, c.z, r * u_scale);
}

vec4 map(vec3 p) {
    float s = u_scale;
    vec3 q = pScale(pTranslate(p, midiCentre()), s);
    q = pRotateY(q, u_time * u_spin);
    vec4 blob = midiBlob(pTwistY(q, u_twist));
    blob.w += fDisplacement(q, u_displacement, MIDI_DISPLACE_FREQ);
#if !SCENE_GLOBAL_LIPSCHITZ
    // Only the blob breaks the distance property, so only the blob is slowed down: dividing it
    // by its own gradient bound keeps every step safe while rays over the floor and into the
    // sky keep full-length steps.
    blob.w = blob.w / midiBlobLipschitz();
#endif
    blob.w = fOpScale(blob.w, s);
    return fOpUnionColor(mapGround(p), blob);
}

// The whole field's gradient bound. By default map() already divides the blob by its own
// bound, so the field is 1-Lipschitz; with SCENE_GLOBAL_LIPSCHITZ the field is left raw and the
// marcher divides every step by the bound instead (how a plain raymarcher would do it).
float sceneLipschitz() {
#if SCENE_GLOBAL_LIPSCHITZ
    return midiBlobLipschitz();
#else
    return 1.0f;
#endif
}
