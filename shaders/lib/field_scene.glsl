// field_scene.glsl - the body shared by the field scenes (field50, field150): floor, map(),
// bounding sphere and Lipschitz bound of FIELD_NX x FIELD_NZ cells of lib/field.glsl. The scene
// file declares its header, `const float FIELD_NX, FIELD_NZ` and includes this once.
#include "lib/common.glsl"
// FIELD_CELL_TABLE (on the compute path: lib/common.glsl SCENE_TABLES): every cell's parameters
// (its lift, turn and kind: uniforms only) computed once per work-group, by all its invocations
// together (sceneSetupLanes), not in every map() call. H200, full lighting, one interleaved run:
// field150 1080p 0.591 -> 0.545 ms, 4K 1.703 -> 1.559; field50 0.462 -> 0.429, 1.346 -> 1.235.
#ifndef FIELD_CELL_TABLE
#define FIELD_CELL_TABLE SCENE_TABLES
#endif
#if FIELD_CELL_TABLE
shared vec4 sceneCells[int(FIELD_NX * FIELD_NZ)];
#define FIELD_CELL_PARAMS(i, j, wave, phase, spin) sceneCells[int(i) + int(j) * int(FIELD_NX)]
#endif
// FIELD_FRAME_INV (on): the blends' reciprocals once per frame (sceneSetup: the frame state on the
// compute path, once per invocation elsewhere), so the shapes' blend and the floor's take no
// division and no branch in any map() call (lib/combinators.glsl fOpUnionSmoothColorInv).
#include "lib/combinators.glsl"
#ifndef FIELD_FRAME_INV
#define FIELD_FRAME_INV 1
#endif
// FIELD_FRAME_DIMS (on): the shapes' dimensions at this size and the shapes' top, once per frame too
// (lib/field.glsl FIELD_DIMS, FIELD_TOP), not in every map() call.
#ifndef FIELD_FRAME_DIMS
#define FIELD_FRAME_DIMS 1
#endif
SCENE_STATE float g_invBlend, g_invFloorBlend;
SCENE_STATE float g_s36, g_s30, g_s26, g_s06, g_s38, g_s11, g_s27, g_s20, g_s165, g_s525, g_radius, g_capsuleInv, g_top;
#if FIELD_FRAME_INV
#define FIELD_BLEND_INV g_invBlend
#endif
#if FIELD_FRAME_DIMS
#define FIELD_DIMS(size) FieldDims(g_s36, g_s30, g_s26, g_s06, g_s38, g_s11, g_s27, g_s20, g_s165, g_s525, g_radius, g_capsuleInv)
#define FIELD_TOP(size, wave) g_top
#endif
#include "lib/field.glsl"
void sceneSetup() {
    g_invBlend = smoothInv(u_blend);
    g_invFloorBlend = smoothInv(u_floorBlend);
    FieldDims m = fieldDims(u_size);
    g_s36 = m.s36; g_s30 = m.s30; g_s26 = m.s26; g_s06 = m.s06; g_s38 = m.s38; g_s11 = m.s11;
    g_s27 = m.s27; g_s20 = m.s20; g_s165 = m.s165; g_s525 = m.s525; g_radius = m.radius; g_capsuleInv = m.capsuleInv;
    g_top = fieldTop(u_size, u_wave);
}
#define SCENE_SETUP 1

// Bounding volume for the renderer (render.glsl BOUNDS): the shapes and the floor apart.
#define SCENE_BOUND 1
#define SCENE_GROUND 1
#define SCENE_BOX 1
// AO's farthest probe first (lib/shading.glsl): H200, full lighting, one interleaved run: field150
// 4K 1.740 -> 1.710 ms, field50 1.369 -> 1.352; midi and character were 2 % slower with it.
#ifndef AO_FARTHEST_FIRST
#define AO_FARTHEST_FIRST 1
#endif

// The floor y = 0, a dark grid under the shapes.
vec4 mapGround(vec3 p) {
    float grid = max(smoothstep(0.47f, 0.5f, abs(fract(p.x) - 0.5f)), smoothstep(0.47f, 0.5f, abs(fract(p.z) - 0.5f)));
    return vec4(mix(vec3(0.16f), vec3(0.10f), grid), p.y);
}

// The wave's phase and the shapes' spin now (map() and the cell table alike).
float fieldPhase() { return u_time * u_speed * 2.0f; }
float fieldSpin() { return u_time * u_spin; }

#if FIELD_CELL_TABLE
#define SCENE_SETUP_LANES 1
void sceneSetupLanes(uint lane, uint lanes) {
    for (uint k = lane; k < uint(FIELD_NX * FIELD_NZ); k += lanes) {
        float j = floor(float(k) / FIELD_NX);
        sceneCells[k] = fieldCellParams(float(k) - j * FIELD_NX, j, u_wave, fieldPhase(), fieldSpin());
    }
}
#endif

// The shapes without the floor, and the floor's blend (render.glsl SCENE_OBJECTS: soft shadows step
// past the floor by the shapes' distance).
#define SCENE_OBJECTS 1
vec4 mapObjects(vec3 p) { return fieldMap(p, FIELD_NX, FIELD_NZ, u_size, u_blend, u_wave, fieldPhase(), fieldSpin()); }
float sceneGroundBlend() { return u_floorBlend; }

#if FIELD_FRAME_INV
#define SCENE_GROUND_SMIN(g, o) sminPolyInv(g, o, u_floorBlend, g_invFloorBlend)
#define SCENE_MAP_OF(g, o) fOpUnionSmoothColorInv(g, o, u_floorBlend, g_invFloorBlend)
vec4 map(vec3 p) { return SCENE_MAP_OF(mapGround(p), mapObjects(p)); }
#else
vec4 map(vec3 p) { return fOpUnionSmoothColor(mapGround(p), mapObjects(p), sceneGroundBlend()); }
#endif

// A sphere and a box around every shape; past them plus the floor blend the smooth union
// leaves the floor exact (the renderer's contract for SCENE_GROUND). The blend lowers the
// shapes' field by at most blend / 4, which the margin covers too; so does it above the box,
// where the field is at least the height above the shapes less blend / 4 + floorBlend / 4.
// Beside the grid fieldMap's cut-off may read up to 1.25 blend under the shapes' distance,
// so the box's sides stand a further blend out (the floor's fillet there follows the cut-off).
float fieldMargin() { return 0.25f * max(u_blend, 0.0f) + max(u_floorBlend, 0.0f) + 0.02f; }
vec4 sceneBound() { return fieldBound(FIELD_NX, FIELD_NZ, u_size, u_wave, fieldMargin()); }
vec3 sceneBoxMax() { return fieldBoxMax(FIELD_NX, FIELD_NZ, u_size, u_wave, fieldMargin() + max(u_blend, 0.0f), fieldMargin()); }
vec3 sceneBoxMin() { return sceneBoxMax() * vec3(-1.0f, 0.0f, -1.0f) - vec3(0.0f, fieldMargin(), 0.0f); }

// Exact shapes, rotations, the two-nearest polynomial blend, the continuous cut-off and the
// floor's smooth union all keep |grad| <= 1 (lib/field.glsl).
float sceneLipschitz() { return 1.0f; }
