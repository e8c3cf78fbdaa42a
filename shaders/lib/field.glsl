// field.glsl - a field of blended shapes on a grid whose cost does not grow with the number
// of shapes: each evaluation looks at the 2x2 cells around the point, never at the others.
//
// Usage (a scene): vec4 m = fieldMap(p, 15.0f, 10.0f, u_size, u_blend, u_wave, phase, spin);
//   nx x nz cells of size 1 centred on the origin in XZ, one shape per cell (sphere, rounded
//   box, upright torus or tilted capsule, chosen per cell), standing on y = 0 and lifted by a
//   wave travelling across the field (0 .. wave); neighbours blend with radius `blend`.
//   FIELD_MAX_BLEND and FIELD_MAX_SIZE are the largest knob values the exactness argument
//   below allows; scenes declare their ranges inside them (tests/sdf checks it).
//
// What is evaluated, and why it is exact near the surfaces:
//   The field is F = sminPoly(d1, d2, blend) where d1 <= d2 are the two smallest distances to
//   ALL shapes (fieldMapAll, the reference the tests compare with). sminPoly of two order
//   statistics of 1-Lipschitz distances is 1-Lipschitz (both partial derivatives lie in [0, 1]
//   and sum to 1), so F is a distance bound of its own zero set, whatever the shapes' order.
//   fieldMap evaluates T, the same over the shapes of the 2x2 cells whose centres surround p,
//   and e, a lower bound of the distance to every other shape (the other cells' centres are
//   at least 1 away along x or z, or farther: fieldExcluded). Each shape lies within
//   FIELD_RADIUS * size of its cell's vertical axis and below fieldTop(). It returns
//   f = min(T, c), c = max(e - 1.25 * blend, p.y - fieldTop() - blend / 4). Then (the second
//   term of c is a bound of F by itself, every shape being below fieldTop, and is what lets a
//   ray above the field step by its height, not by the cell gap):
//   - where F < e - 1.25 blend: the nearest shape is within F + blend/4 < e - blend, so it is
//     one of the four, and any shape left out is >= blend farther than it, so it changes no
//     smooth minimum: T = F and f = F (exact, the surface and everything within
//     1 - FIELD_RADIUS * size - 1.25 blend of it: 0.2 at the scenes' defaults, 0.11 at worst);
//   - elsewhere f <= c <= F: still a bound, and never <= 0 (e >= 1 - radius);
//   - e is continuous (along x the cut moves from one cell to the next where both candidate
//     columns are 1 away), so f is continuous and 1-Lipschitz: sceneLipschitz() stays 1, and
//     normals, AO probes (h <= 0.16, inside the exact zone but at the largest knobs) and
//     penumbrae near surfaces see F itself.
#ifndef SDF_LIB_FIELD_GLSL
#define SDF_LIB_FIELD_GLSL
#include "lib/common.glsl"
#include "lib/primitives.glsl"
#include "lib/domain.glsl"
#include "lib/combinators.glsl"

const float FIELD_UNIT = 1.17f;      // shape dimensions below are in units of size * FIELD_UNIT
const float FIELD_RADIUS = 0.45f;    // every shape within this * size of its cell's axis (XZ): 0.38 * 1.17
const float FIELD_MAX_SIZE = 1.0f;
const float FIELD_MAX_BLEND = 0.35f; // 1 - 0.45 - 1.25 * 0.35 = 0.11 > 0 at the largest size

// Albedo of a cell: a six-colour palette walked along the diagonal.
vec3 fieldColor(float i, float j) {
    float c = mod(i + 2.0f * j, 6.0f);
    if (c < 0.5f) return vec3(0.92f, 0.26f, 0.21f);
    if (c < 1.5f) return vec3(0.98f, 0.66f, 0.14f);
    if (c < 2.5f) return vec3(0.20f, 0.70f, 0.45f);
    if (c < 3.5f) return vec3(0.18f, 0.45f, 0.92f);
    if (c < 4.5f) return vec3(0.62f, 0.30f, 0.85f);
    return vec3(0.90f, 0.90f, 0.86f);
}

// Height of the wave under cell (i, j): 0 .. wave, travelling along the diagonal.
float fieldLift(float i, float j, float wave, float phase) {
    return wave * (0.5f + 0.5f * sin(phase - 0.55f * (i + j)));
}

// Highest point of any shape: the capsule's top at lift = wave.
float fieldTop(float size, float wave) { return 0.95f * FIELD_UNIT * max(size, 0.05f) + max(wave, 0.0f); }
#ifndef FIELD_TOP
#define FIELD_TOP(size, wave) fieldTop(size, wave)
#endif

// What a cell's shape depends on besides the point: (lift, cos turn, sin turn, kind). Uniforms and the
// cell only, so a scene may compute it once per work-group (field_scene.glsl FIELD_CELL_TABLE).
vec4 fieldCellParams(float i, float j, float wave, float phase, float spin) {
    float lift = fieldLift(i, j, wave, phase);
    float turn = spin * (mod(i + j, 2.0f) < 0.5f ? 1.0f : -1.0f) + 0.9f * i + 0.4f * j;
    float kind = mod(i + 3.0f * j + floor(0.5f * i), 4.0f);
    return vec4(lift, cos(turn), sin(turn), kind);
}

// A size's dimensions (size * FIELD_UNIT times each shape's proportions; radius: FIELD_RADIUS *
// size; capsuleInv: 1 / the capsule's squared length). FIELD_DIMS(size): computed here in every
// map() call, unless the scene keeps the frame's (lib/field_scene.glsl FIELD_FRAME_DIMS).
struct FieldDims {
    float s36, s30, s26, s06, s38, s11, s27, s20, s165, s525, radius, capsuleInv;
};
FieldDims fieldDims(float size) {
    float s = max(size, 0.05f) * FIELD_UNIT;
    float s165 = 0.165f * s, s525 = 0.525f * s;
    return FieldDims(0.36f * s, 0.30f * s, 0.26f * s, 0.06f * s, 0.38f * s, 0.11f * s, 0.27f * s, 0.2f * s, s165, s525,
                     FIELD_RADIUS * max(size, 0.05f), 1.0f / max(s165 * s165 + s525 * s525, 1e-12f));
}
#ifndef FIELD_DIMS
#define FIELD_DIMS(size) fieldDims(size)
#endif

// The shape of a cell with parameters c (fieldCellParams), q relative to the cell's centre on the
// floor: its distance, exact; every shape lies within FIELD_RADIUS * size of the cell's vertical
// axis, at y >= lift >= 0.
float fieldShapeOf(vec3 q, float size, vec4 c) {
    FieldDims m = FIELD_DIMS(size);
    float lift = c.x;
    float kind = c.w;
    float d;
    if (kind < 0.5f) {
        d = fSphere(pTranslate(q, vec3(0.0f, m.s36 + lift, 0.0f)), m.s36);                  // r 0.36
    } else if (kind < 1.5f) {
        vec3 b = pRotateYcs(pTranslate(q, vec3(0.0f, m.s30 + lift, 0.0f)), c.y, c.z);
        d = fRoundBox(b, vec3(m.s26, m.s30, m.s26), m.s06);                                  // corner 0.368
    } else if (kind < 2.5f) {
        vec3 t = pRotateYcs(pTranslate(q, vec3(0.0f, m.s38 + lift, 0.0f)), c.y, c.z);
        d = fTorus(pRotateX(t, 0.5f * PI), m.s11, m.s27);                                    // outer 0.38
    } else {
        vec3 a = vec3(0.0f, m.s20 + lift, 0.0f);
        vec3 tip = vec3(m.s165 * c.y, m.s525, m.s165 * c.z);                                 // 0.55 long, tilted
        d = fCapsuleInv(q, a, a + tip, m.s20, m.capsuleInv);                                 // 0.165 + 0.2
    }
    return d;
}
float fieldShape(vec3 q, float i, float j, float size, float wave, float phase, float spin) {
    return fieldShapeOf(q, size, fieldCellParams(i, j, wave, phase, spin));
}

// A cell's parameters inside fieldMap: computed, unless the scene keeps a table (FIELD_CELL_TABLE,
// which defines FIELD_CELL_PARAMS). They are read after the skip test: reading them before it, to
// bound each shape in height as well (the slab lift .. lift + its height), was exact but slower on
// the H200 (field150 1080p 0.543 -> 0.639 ms, field50 0.426 -> 0.500; docs/performance.md, session 25).
#ifndef FIELD_CELL_PARAMS
#define FIELD_CELL_PARAMS(i, j, wave, phase, spin) fieldCellParams(i, j, wave, phase, spin)
#endif

// The two nearest of a set of shapes: (i, j, 0, distance) each; colours are looked up last.
struct FieldPair {
    vec4 near;
    vec4 next;
};

FieldPair fieldInsert(FieldPair n, vec4 m) {
    if (m.w < n.near.w) return FieldPair(m, n.near);
    if (m.w < n.next.w) return FieldPair(n.near, m);
    return n;
}

// Inserts cell (i, j)'s shape at p into the pair. Skips cells outside the nx x nz grid, and
// (exactly) a shape whose cylinder is no nearer than the pair's second, or at least `blend`
// farther than its nearest: the blend of two distances k or more apart is the nearer one, colour
// and all (sminPoly, blendWeight), and the nearest only comes closer, so the field is unchanged.
FieldPair fieldCell(FieldPair n, vec3 p, float i, float j, float nx, float nz, float size, float blend, float wave,
                    float phase, float spin) {
    if (i < -0.5f || j < -0.5f || i > nx - 0.5f || j > nz - 0.5f) return n;
    vec3 q = p - vec3(i - 0.5f * (nx - 1.0f), 0.0f, j - 0.5f * (nz - 1.0f));
    float reach = min(n.next.w, n.near.w + max(blend, 0.0f));
    if (length(vec2(q.x, q.z)) - FIELD_DIMS(size).radius >= reach) return n;
    return fieldInsert(n, vec4(i, j, 0.0f, fieldShapeOf(q, size, FIELD_CELL_PARAMS(i, j, wave, phase, spin))));
}

// The pair's blend with its colours.
// FIELD_BLEND_INV: an expression for smoothInv(blend) that the scene computed once (lib/field_scene.glsl's
// frame state); then the blend takes no division and no branch per call.
vec4 fieldBlend(FieldPair n, float blend) {
    vec3 a = fieldColor(n.near.x, n.near.y);
    vec3 b = n.next.w < 1e8f ? fieldColor(n.next.x, n.next.y) : a;
#ifdef FIELD_BLEND_INV
    return fOpUnionSmoothColorInv(vec4(a.x, a.y, a.z, n.near.w), vec4(b.x, b.y, b.z, n.next.w), blend, FIELD_BLEND_INV);
#else
    return fOpUnionSmoothColor(vec4(a.x, a.y, a.z, n.near.w), vec4(b.x, b.y, b.z, n.next.w), blend);
#endif
}

// Distance along one axis (u = cell coordinate, centre of cell k at u = k) from p to the
// centres not in the pair (i0, i0 + 1), or 1e9 if there are none on either side.
float fieldAxisGap(float u, float i0, float n) {
    float below = i0 > 0.5f ? u - (i0 - 1.0f) : 1e9f;
    float above = i0 + 2.0f < n - 0.5f ? (i0 + 2.0f) - u : 1e9f;
    return min(below, above);
}

// Distance from (u, v) to the rectangle [0, nx-1] x [0, nz-1] of all centres.
float fieldGridDistance(float u, float v, float nx, float nz) {
    vec2 d = max(vec2(-u, -v), vec2(u - (nx - 1.0f), v - (nz - 1.0f)));
    return length(max(d, vec2(0.0f)));
}

// A lower bound of the distance from p to every shape outside the 2x2 cells (i0, j0) ..
// (i0 + 1, j0 + 1): the nearer of the gaps along x and z, or the distance to the whole grid,
// less the shapes' radius. Continuous in p.
float fieldExcluded(float u, float v, float i0, float j0, float nx, float nz, float size) {
    float gap = min(fieldAxisGap(u, i0, nx), fieldAxisGap(v, j0, nz));
    return max(gap, fieldGridDistance(u, v, nx, nz)) - FIELD_DIMS(size).radius;
}

// The field of nx x nz shapes at p: four shapes evaluated, exact within the blend radius.
vec4 fieldMap(vec3 p, float nx, float nz, float size, float blend, float wave, float phase, float spin) {
    float u = p.x + 0.5f * (nx - 1.0f);   // cell coordinates: cell (i, j)'s centre at (u, v) = (i, j)
    float v = p.z + 0.5f * (nz - 1.0f);
    float i0 = clamp(floor(u), 0.0f, nx - 2.0f);
    float j0 = clamp(floor(v), 0.0f, nz - 2.0f);
    // nearest centre first, so the cylinder test skips more of the others. FIELD_NEAREST_FIRST 0: the
    // cells in one order, so the lanes of a warp in the same 2x2 cells take the same shape's branch
    // at each turn of the loop: the same pixels, but slower on the H200 (field50 / field150 at 1080p
    // 0.562 / 0.694 against 0.520 / 0.641 ms, 4K 1.529 / 1.943 against 1.433 / 1.797: session 19)
#ifndef FIELD_NEAREST_FIRST
#define FIELD_NEAREST_FIRST 1
#endif
#if FIELD_NEAREST_FIRST
    float di = u - i0 < 0.5f ? 0.0f : 1.0f;
    float dj = v - j0 < 0.5f ? 0.0f : 1.0f;
#else
    const float di = 0.0f, dj = 0.0f;
#endif
    FieldPair n = FieldPair(vec4(0.0f, 0.0f, 0.0f, 1e9f), vec4(0.0f, 0.0f, 0.0f, 1e9f));
    // one call site in a rolled loop (SDF_LOOP_ZERO): fieldShape's code once, not four times
    for (int c = SDF_LOOP_ZERO; c < 4; c++)
        n = fieldCell(n, p, i0 + ((c & 1) == 0 ? di : 1.0f - di), j0 + (c < 2 ? dj : 1.0f - dj), nx, nz, size, blend, wave, phase, spin);
    vec4 m = fieldBlend(n, blend);
    float k = max(blend, 0.0f);
    m.w = min(m.w, max(fieldExcluded(u, v, i0, j0, nx, nz, size) - 1.25f * k, p.y - FIELD_TOP(size, wave) - 0.25f * k));
    return m;
}

// The reference: the same field over every shape (nx * nz evaluations). Tests only.
vec4 fieldMapAll(vec3 p, float nx, float nz, float size, float blend, float wave, float phase, float spin) {
    FieldPair n = FieldPair(vec4(0.0f, 0.0f, 0.0f, 1e9f), vec4(0.0f, 0.0f, 0.0f, 1e9f));
    for (int j = 0; j < int(nz); j++)
        for (int i = 0; i < int(nx); i++) {
            vec3 q = p - vec3(float(i) - 0.5f * (nx - 1.0f), 0.0f, float(j) - 0.5f * (nz - 1.0f));
            n = fieldInsert(n, vec4(float(i), float(j), 0.0f, fieldShape(q, float(i), float(j), size, wave, phase, spin)));
        }
    return fieldBlend(n, blend);
}

// A sphere around every shape of the field (for SCENE_BOUND), widened by `extra`.
vec4 fieldBound(float nx, float nz, float size, float wave, float extra) {
    float top = fieldTop(size, wave);
    float r = FIELD_RADIUS * max(size, 0.05f);
    float hx = 0.5f * (nx - 1.0f) + r;
    float hz = 0.5f * (nz - 1.0f) + r;
    return vec4(0.0f, 0.5f * top, 0.0f, sqrt(hx * hx + hz * hz + 0.25f * top * top) + extra);
}

// The corner (+x, top, +z) of a box around every shape of the field (symmetric in x and z),
// widened by `side` in x and z and by `up` at the top.
vec3 fieldBoxMax(float nx, float nz, float size, float wave, float side, float up) {
    float r = FIELD_RADIUS * max(size, 0.05f);
    return vec3(0.5f * (nx - 1.0f) + r + side, fieldTop(size, wave) + up, 0.5f * (nz - 1.0f) + r + side);
}

#endif
