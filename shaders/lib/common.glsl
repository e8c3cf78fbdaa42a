// common.glsl - constants and small scalar/vector helpers used by every SDF file.
//
// Usage: #include "lib/common.glsl", then PI, TAU, saturate(x), dot2(v), vmax(v), vmin(v),
// sgn(x) (never 0), square(x), safeNormalize(v), octEncode(n), octDecode(e).
// Written in the GLSL subset that also compiles as C++ (src/sdf/glsl_prelude.h): no
// swizzles, no inout/out, float literals with `f`.
#ifndef SDF_LIB_COMMON_GLSL
#define SDF_LIB_COMMON_GLSL

// Declares a scene's per-invocation state: `SCENE_STATE vec3 g_head;` (written by the scene's
// sceneSetup(), read by map(); render.glsl: SCENE_SETUP). Private to the invocation in GLSL,
// thread_local in C++. (Kept per invocation: one invocation of the work-group computing it for the
// others into shared memory cost character 15 % at 1080p on the H200 and saved nothing at 4K.)
#ifndef SCENE_STATE
#define SCENE_STATE
#endif
// SCENE_SETUP_FRAME (1 on the compute path): sceneSetup() runs once per frame, in the cone
// pre-pass's first invocation (or a dispatch of its own without the pre-pass), which stores the
// state in a buffer; every pixel of the frame loads it from there as a uniform block
// (main_comp.glsl; the blocks are generated from the SCENE_STATE lines, src/shader/shader.cpp
// SceneStateBlocks: a line it cannot read for certain, inside an #if or with an initialiser, keeps
// the program's setup per invocation).
#if defined(SDFVJ_COMPUTE) && !defined(SCENE_SETUP_FRAME)
#define SCENE_SETUP_FRAME 1
#endif
#ifndef SCENE_SETUP_FRAME
#define SCENE_SETUP_FRAME 0
#endif

// SCENE_TABLES (1 on the compute path): a scene may keep tables of values that depend on uniforms
// only (the fields' cells) in the work-group's shared memory, filled by all of the group's
// invocations together before any map() (`#define SCENE_SETUP_LANES 1`, `void sceneSetupLanes(uint
// lane, uint lanes)`; main_comp.glsl). Elsewhere (the fragment path, C++) it computes those values
// where it needs them.
#if defined(SDFVJ_COMPUTE) && !defined(SCENE_TABLES)
#define SCENE_TABLES 1
#endif
#ifndef SCENE_TABLES
#define SCENE_TABLES 0
#endif

// Where a loop around a map() call (or other heavy code) starts: render/uniforms.glsl makes it a 0
// the GLSL compiler cannot see, so the loop stays rolled and its body is inlined once, not once per
// iteration (less for the driver to compile and for the GPU's instruction cache); plain 0 in C++.
#ifndef SDF_LOOP_ZERO
#define SDF_LOOP_ZERO 0
#endif

// Irrational constants are computed from exactly representable literals: a `f` literal
// is rounded to float even in the double build, an expression of 3.0f is not.
const float PI = acos(-1.0f);
const float TAU = 2.0f * acos(-1.0f);
const float SQRT3 = sqrt(3.0f);

// clamp to [0, 1]
float saturate(float x) { return clamp(x, 0.0f, 1.0f); }
vec3 saturate(vec3 v) { return clamp(v, 0.0f, 1.0f); }

// squared length
float dot2(vec2 v) { return dot(v, v); }
float dot2(vec3 v) { return dot(v, v); }

// largest / smallest component
float vmax(vec2 v) { return max(v.x, v.y); }
float vmax(vec3 v) { return max(max(v.x, v.y), v.z); }
float vmin(vec2 v) { return min(v.x, v.y); }
float vmin(vec3 v) { return min(min(v.x, v.y), v.z); }

// sign that is never 0 (sign(0) = 0 breaks mirror and fold operators)
float sgn(float x) { return x < 0.0f ? -1.0f : 1.0f; }

float square(float x) { return x * x; }

// normalize that returns (0, 1, 0) instead of NaN for a zero vector (flat fields, the
// inside of a degenerate primitive)
vec3 safeNormalize(vec3 v) {
    float l = length(v);
    return l > 1e-20f ? v / l : vec3(0.0f, 1.0f, 0.0f);
}

// Octahedral encoding of a unit vector into two floats (DEBUG_VIEW 4).
vec2 octEncode(vec3 n) {
    float s = abs(n.x) + abs(n.y) + abs(n.z);
    float x = n.x / max(s, 1e-20f);
    float y = n.y / max(s, 1e-20f);
    if (n.z < 0.0f) {
        float ox = (1.0f - abs(y)) * sgn(x);
        float oy = (1.0f - abs(x)) * sgn(y);
        x = ox;
        y = oy;
    }
    return vec2(x, y);
}

// octEncode's inverse (render.glsl's quad_reflections reads its normals back).
vec3 octDecode(vec2 e) {
    vec3 n = vec3(e.x, e.y, 1.0f - abs(e.x) - abs(e.y));
    if (n.z < 0.0f) n = vec3((1.0f - abs(e.y)) * sgn(e.x), (1.0f - abs(e.x)) * sgn(e.y), n.z);
    return normalize(n);
}

#endif
