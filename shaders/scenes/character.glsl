/*{
  "NAME": "character", "DESCRIPTION": "A humanoid of 15 spheres and capsules blended into each other and into the floor, walking in place and waving.",
  "INPUTS": [
    {"NAME": "speed", "TYPE": "float", "DEFAULT": 1.0, "MIN": 0.0, "MAX": 3.0, "LABEL": "Walk speed"},
    {"NAME": "wave", "TYPE": "float", "DEFAULT": 1.0, "MIN": 0.0, "MAX": 1.0, "LABEL": "Wave"},
    {"NAME": "blend", "TYPE": "float", "DEFAULT": 0.06, "MIN": 0.0, "MAX": 0.25, "LABEL": "Joint blend"},
    {"NAME": "floorBlend", "TYPE": "float", "DEFAULT": 0.12, "MIN": 0.0, "MAX": 0.5, "LABEL": "Floor blend"}
  ],
  "EFFECTS": {"SHADOWS": "improved", "AO": true, "SPECULAR": true, "PBR": false, "REFLECTIONS": 0, "FOG": true, "NORMALS": "forward"},
  "CAMERA": {"POSITION": [1.2, 1.5, -4.0], "TARGET": [0, 0.95, 0], "FOV": 40},
  "LIGHT": {"DIRECTION": [0.5, 0.8, -0.35], "COLOR": [1, 0.95, 0.88]},
  "MATERIAL": {"ROUGHNESS": 0.5, "METALNESS": 0.0}
}*/
// character.glsl - a 15-part humanoid (head, torso, pelvis, upper arms, forearms, hands,
// thighs, shins, feet) of spheres and capsules, smooth-unioned at the joints
// (u_blend) and into the floor (u_floorBlend). u_time drives a walk cycle (u_speed) and a
// right-arm wave (u_wave, 0 = swings with the walk, 1 = waves). Faces -Z (the camera).
#include "lib/common.glsl"
#include "lib/primitives.glsl"
#include "lib/domain.glsl"
#include "lib/combinators.glsl"

// Unit direction of a limb hanging down and swung forward (towards -Z) by angle a.
vec3 limbDir(float a) { return vec3(0.0f, -cos(a), -sin(a)); }

// Bounding volume for the renderer (render.glsl BOUNDS): the figure and the floor apart, and a box
// around this frame's pose (sceneSetup) inside the sphere: a floor point beside it is shaded with
// the floor alone, and a ray that enters the sphere but not the box marches nothing.
#define SCENE_BOUND 1
#define SCENE_GROUND 1
#ifndef SCENE_BOX   // (a copy defines it 0 to measure the sphere alone)
#define SCENE_BOX 1
#endif

// The compute path's work-group (render/main_comp.glsl): 16x16, not 8x8. On the H200, against
// 8x8, 8x4, 16x8 and 8x16 in one interleaved run: 4K full lighting 0.854 -> 0.798 ms, 1080p
// 0.309 -> 0.298, the 7680x4320 show 5.13 -> 4.67 (the other scenes are fastest in 8x8 or within
// 1 % of it: docs/performance.md). The same pixels in any shape. Guarded, so a copy can try another.
#ifndef WORKGROUP_X
#define WORKGROUP_X 16
#define WORKGROUP_Y 16
#endif

// The floor y = 0 with its grid lines.
vec4 mapGround(vec3 p) {
    float grid = max(smoothstep(0.46f, 0.5f, abs(fract(p.x) - 0.5f)), smoothstep(0.46f, 0.5f, abs(fract(p.z) - 0.5f)));
    return vec4(mix(vec3(0.45f), vec3(0.25f), grid), p.y);
}

SCENE_STATE vec3 g_hipL;
SCENE_STATE vec3 g_hipR;
SCENE_STATE vec3 g_kneeL;
SCENE_STATE vec3 g_kneeR;
SCENE_STATE vec3 g_ankleL;
SCENE_STATE vec3 g_ankleR;
SCENE_STATE vec3 g_shoulderL;
SCENE_STATE vec3 g_shoulderR;
SCENE_STATE vec3 g_elbowL;
SCENE_STATE vec3 g_handL;
SCENE_STATE vec3 g_elbowR;
SCENE_STATE vec3 g_handR;
SCENE_STATE vec3 g_pelvis;
SCENE_STATE vec3 g_chest;
SCENE_STATE vec3 g_head;
// Each limb's bounding sphere (centre: its middle joint; radius: the farther end's reach plus that
// part's radius), for map()'s part skip.
SCENE_STATE float g_armRadiusL;
SCENE_STATE float g_armRadiusR;
SCENE_STATE float g_legRadiusL;
SCENE_STATE float g_legRadiusR;
// Each capsule's 1 / |b - a|^2 (fCapsuleInv): CHARACTER_CAPSULE_INV.
#ifndef CHARACTER_CAPSULE_INV
#ifdef QUICK_TIER
#define CHARACTER_CAPSULE_INV 0
#else
#define CHARACTER_CAPSULE_INV 1
#endif
#endif
SCENE_STATE float g_ilTorso, g_ilUpperArmL, g_ilForearmL, g_ilUpperArmR, g_ilForearmR;
SCENE_STATE float g_ilThighL, g_ilShinL, g_ilFootL, g_ilThighR, g_ilShinR, g_ilFootR;
SCENE_STATE vec3 g_boxLo;   // the box around this frame's parts, margins included (sceneBoxMin/Max)
SCENE_STATE vec3 g_boxHi;
// The skeleton for this frame (u_time, u_speed, u_wave): once per invocation (render.glsl's
// SCENE_SETUP), not in every map() call. NVIDIA H200, 4K: 1.34 -> 1.05 ms (docs/performance.md).
void sceneSetup() {
    float phase = u_time * u_speed * 4.0f;
    float swing = 0.45f * sin(phase);
    float bob = 0.03f * abs(cos(phase));
    vec3 up = vec3(0.0f, bob, 0.0f);

    // legs: thigh swings, knee bends on the back swing
    g_hipL = vec3(0.12f, 0.92f, 0.0f) + up;
    g_hipR = vec3(-0.12f, 0.92f, 0.0f) + up;
    float kneeBendL = 0.6f * max(0.0f, -sin(phase - 0.8f));
    float kneeBendR = 0.6f * max(0.0f, sin(phase - 0.8f));
    g_kneeL = g_hipL + 0.42f * limbDir(swing);
    g_kneeR = g_hipR + 0.42f * limbDir(-swing);
    g_ankleL = g_kneeL + 0.40f * limbDir(swing - kneeBendL);
    g_ankleR = g_kneeR + 0.40f * limbDir(-swing - kneeBendR);

    // arms: the left swings against its leg; the right swings or waves
    g_shoulderL = vec3(0.26f, 1.42f, 0.0f) + up;
    g_shoulderR = vec3(-0.26f, 1.42f, 0.0f) + up;
    g_elbowL = g_shoulderL + 0.30f * limbDir(-0.8f * swing);
    g_handL = g_elbowL + 0.28f * limbDir(-0.8f * swing + 0.3f);
    vec3 elbowSwing = g_shoulderR + 0.30f * limbDir(0.8f * swing);
    vec3 handSwing = elbowSwing + 0.28f * limbDir(0.8f * swing + 0.3f);
    float waveAngle = 0.45f * sin(u_time * 7.0f);
    vec3 elbowWave = g_shoulderR + 0.30f * normalize(vec3(-0.8f, 0.5f, -0.1f));
    vec3 handWave = elbowWave + 0.28f * vec3(-sin(waveAngle), cos(waveAngle), 0.0f);
    g_elbowR = mix(elbowSwing, elbowWave, u_wave);
    g_handR = mix(handSwing, handWave, u_wave);

    g_pelvis = vec3(0.0f, 0.98f, 0.0f) + up;
    g_chest = vec3(0.0f, 1.36f, 0.0f) + up;
    g_head = vec3(0.0f, 1.70f, 0.0f) + up;

    g_armRadiusL = max(length(g_shoulderL - g_elbowL) + 0.065f, length(g_handL - g_elbowL) + 0.06f) + 1e-3f;
    g_armRadiusR = max(length(g_shoulderR - g_elbowR) + 0.065f, length(g_handR - g_elbowR) + 0.06f) + 1e-3f;
    vec3 toe = vec3(0.0f, -0.02f, -0.14f);
    g_legRadiusL = max(max(length(g_hipL - g_kneeL) + 0.085f, length(g_ankleL - g_kneeL) + 0.07f),
                       length(g_ankleL + toe - g_kneeL) + 0.06f) + 1e-3f;
    g_legRadiusR = max(max(length(g_hipR - g_kneeR) + 0.085f, length(g_ankleR - g_kneeR) + 0.07f),
                       length(g_ankleR + toe - g_kneeR) + 0.06f) + 1e-3f;

    // The box: every joint +- the radius of the parts that end there (a capsule lies in the box of
    // its two end balls; the torso's lower end, pelvis + 0.1 up, lies in the pelvis's and the chest's),
    // widened as the sphere is: the joint blends swell the figure by at most blend / 4, and past
    // blend + floorBlend the floor's smooth union leaves the floor exact (SCENE_GROUND's contract);
    // above the top, map() >= the height over it (render.glsl SCENE_BOX).
    vec3 lo = min(min(g_head - vec3(0.14f), g_pelvis - vec3(0.19f)), g_chest - vec3(0.19f));
    vec3 hi = max(max(g_head + vec3(0.14f), g_pelvis + vec3(0.19f)), g_chest + vec3(0.19f));
    lo = min(lo, min(min(g_shoulderL, g_shoulderR), min(g_elbowL, g_elbowR)) - vec3(0.065f));
    hi = max(hi, max(max(g_shoulderL, g_shoulderR), max(g_elbowL, g_elbowR)) + vec3(0.065f));
    lo = min(lo, min(g_handL, g_handR) - vec3(0.06f));
    hi = max(hi, max(g_handL, g_handR) + vec3(0.06f));
    lo = min(lo, min(min(g_hipL, g_hipR), min(g_kneeL, g_kneeR)) - vec3(0.085f));
    hi = max(hi, max(max(g_hipL, g_hipR), max(g_kneeL, g_kneeR)) + vec3(0.085f));
    lo = min(lo, min(g_ankleL, g_ankleR) - vec3(0.07f));
    hi = max(hi, max(g_ankleL, g_ankleR) + vec3(0.07f));
    lo = min(lo, min(g_ankleL, g_ankleR) + toe - vec3(0.06f));
    hi = max(hi, max(g_ankleL, g_ankleR) + toe + vec3(0.06f));
    g_ilTorso = capsuleInvLen2(g_pelvis + vec3(0.0f, 0.1f, 0.0f), g_chest);
    g_ilUpperArmL = capsuleInvLen2(g_shoulderL, g_elbowL);
    g_ilForearmL = capsuleInvLen2(g_elbowL, g_handL);
    g_ilUpperArmR = capsuleInvLen2(g_shoulderR, g_elbowR);
    g_ilForearmR = capsuleInvLen2(g_elbowR, g_handR);
    g_ilThighL = capsuleInvLen2(g_hipL, g_kneeL);
    g_ilShinL = capsuleInvLen2(g_kneeL, g_ankleL);
    g_ilFootL = capsuleInvLen2(g_ankleL, g_ankleL + toe);
    g_ilThighR = capsuleInvLen2(g_hipR, g_kneeR);
    g_ilShinR = capsuleInvLen2(g_kneeR, g_ankleR);
    g_ilFootR = capsuleInvLen2(g_ankleR, g_ankleR + toe);
    float margin = max(u_blend, 0.0f) + max(u_floorBlend, 0.0f) + 0.02f;
    g_boxLo = lo - vec3(margin);
    g_boxHi = hi + vec3(margin);
}
#define SCENE_SETUP 1

// The part skip (CHARACTER_SKIP, on by default): the polynomial smooth union of two distances k
// or more apart is the nearer one, colour included (sminPoly, blendWeight), and the running
// distance only falls, so a limb whose bounding sphere is more than k beyond the body so far
// changes nothing and is not evaluated. The field is the same; each limb is unioned in one piece
// (upper part, lower part, end), which orders the unions by limb.
// A save's quick tier (QUICK_TIER, src/render/program.cpp) evaluates every part, and divides per
// capsule (below): the same field, and NVIDIA links it in 0.85 of the time (session 43; its frames
// are slower, for the seconds until the optimized program follows).
#ifndef CHARACTER_SKIP
#ifdef QUICK_TIER
#define CHARACTER_SKIP 0
#else
#define CHARACTER_SKIP 1
#endif
#endif
bool farPart(vec3 p, vec3 centre, float radius, float body, float k) {
#if CHARACTER_SKIP
    return length(p - centre) - radius > body + max(k, 0.0f);
#else
    return false;
#endif
}

#if CHARACTER_CAPSULE_INV
#define CAPSULE(p, a, b, r, il) fCapsuleInv(p, a, b, r, il)
#else
#define CAPSULE(p, a, b, r, il) fCapsule(p, a, b, r)
#endif
// The figure without the floor, and the floor's blend (render.glsl SCENE_OBJECTS: soft shadows step
// past the floor by the figure's distance); map() is their smooth union.
#define SCENE_OBJECTS 1
float sceneGroundBlend() { return u_floorBlend; }
vec4 mapObjects(vec3 p) {
    const vec3 skin = vec3(0.80f, 0.52f, 0.38f);
    const vec3 shirt = vec3(0.75f, 0.12f, 0.10f);
    const vec3 jeans = vec3(0.10f, 0.16f, 0.42f);
    const vec3 shoes = vec3(0.06f, 0.05f, 0.05f);
    float k = u_blend;

    vec4 body = vec4(skin, fSphere(p - g_head, 0.14f));
    body = fOpUnionSmoothColor(body, vec4(shirt, CAPSULE(p, g_pelvis + vec3(0.0f, 0.1f, 0.0f), g_chest, 0.19f, g_ilTorso)), k);
    body = fOpUnionSmoothColor(body, vec4(jeans, fSphere(p - g_pelvis, 0.17f)), k);
    if (!farPart(p, g_elbowL, g_armRadiusL, body.w, k)) {
        body = fOpUnionSmoothColor(body, vec4(shirt, CAPSULE(p, g_shoulderL, g_elbowL, 0.065f, g_ilUpperArmL)), k);
        body = fOpUnionSmoothColor(body, vec4(skin, CAPSULE(p, g_elbowL, g_handL, 0.05f, g_ilForearmL)), k);
        body = fOpUnionSmoothColor(body, vec4(skin, fSphere(p - g_handL, 0.06f)), k);
    }
    if (!farPart(p, g_elbowR, g_armRadiusR, body.w, k)) {
        body = fOpUnionSmoothColor(body, vec4(shirt, CAPSULE(p, g_shoulderR, g_elbowR, 0.065f, g_ilUpperArmR)), k);
        body = fOpUnionSmoothColor(body, vec4(skin, CAPSULE(p, g_elbowR, g_handR, 0.05f, g_ilForearmR)), k);
        body = fOpUnionSmoothColor(body, vec4(skin, fSphere(p - g_handR, 0.06f)), k);
    }
    if (!farPart(p, g_kneeL, g_legRadiusL, body.w, k)) {
        body = fOpUnionSmoothColor(body, vec4(jeans, CAPSULE(p, g_hipL, g_kneeL, 0.085f, g_ilThighL)), k);
        body = fOpUnionSmoothColor(body, vec4(jeans, CAPSULE(p, g_kneeL, g_ankleL, 0.07f, g_ilShinL)), k);
        body = fOpUnionSmoothColor(body, vec4(shoes, CAPSULE(p, g_ankleL, g_ankleL + vec3(0.0f, -0.02f, -0.14f), 0.06f, g_ilFootL)), k);
    }
    if (!farPart(p, g_kneeR, g_legRadiusR, body.w, k)) {
        body = fOpUnionSmoothColor(body, vec4(jeans, CAPSULE(p, g_hipR, g_kneeR, 0.085f, g_ilThighR)), k);
        body = fOpUnionSmoothColor(body, vec4(jeans, CAPSULE(p, g_kneeR, g_ankleR, 0.07f, g_ilShinR)), k);
        body = fOpUnionSmoothColor(body, vec4(shoes, CAPSULE(p, g_ankleR, g_ankleR + vec3(0.0f, -0.02f, -0.14f), 0.06f, g_ilFootR)), k);
    }

    return body;
}

vec4 map(vec3 p) { return fOpUnionSmoothColor(mapGround(p), mapObjects(p), sceneGroundBlend()); }

// A sphere around the figure for every knob position and time: every part lies within 1.3 of
// (0, 0.95, 0) (the raised waving hand and the swung foot are the farthest); the joint blends
// can swell it by about the blend radius, and beyond radius + floor blend the smooth union with
// the floor leaves the floor exact (the renderer's contract for SCENE_GROUND).
vec4 sceneBound() { return vec4(0.0f, 0.95f, 0.0f, 1.3f + max(u_blend, 0.0f) + max(u_floorBlend, 0.0f) + 0.02f); }

vec3 sceneBoxMin() { return g_boxLo; }
vec3 sceneBoxMax() { return g_boxHi; }

// Spheres and capsules are exact; smooth unions keep |grad| <= 1.
float sceneLipschitz() { return 1.0f; }
