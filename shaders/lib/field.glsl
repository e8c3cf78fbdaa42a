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
const float FIELD_WAVE_STEP = 0.55f; // the wave's phase step from one cell to the next along i + j
const float FIELD_TURN_I = 0.9f;     // a shape's fixed turn per cell along i
const float FIELD_TURN_J = 0.4f;     // and along j

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
    return wave * (0.5f + 0.5f * sin(phase - FIELD_WAVE_STEP * (i + j)));
}

// Highest point of any shape: the capsule's top at lift = wave.
float fieldTop(float size, float wave) { return 0.95f * FIELD_UNIT * max(size, 0.05f) + max(wave, 0.0f); }

// Where cell (i, j)'s shape stands besides its position: its lift and (cos, sin) of its turn.
struct FieldPose {
    float lift;
    vec2 turn;
};

// The turn of cell (i, j): spin in alternate directions on a chequerboard, plus a fixed angle.
float fieldTurn(float i, float j, float spin) {
    return spin * (mod(i + j, 2.0f) < 0.5f ? 1.0f : -1.0f) + FIELD_TURN_I * i + FIELD_TURN_J * j;
}

// The pose of one cell straight from its formulas (fieldMapAll; fieldBlockPoses gives the same
// for a 2x2 block with two sin/cos pairs in all).
FieldPose fieldPose(float i, float j, float wave, float phase, float spin) {
    float t = fieldTurn(i, j, spin);
    return FieldPose(fieldLift(i, j, wave, phase), vec2(cos(t), sin(t)));
}

// pRotateY(q, turn) with the turn's (cos, sin).
vec3 fieldTurnY(vec3 q, vec2 cs) { return vec3(cs.x * q.x - cs.y * q.z, q.y, cs.y * q.x + cs.x * q.z); }

// The shape of cell (i, j), q relative to the cell's centre on the floor: its distance, exact;
// every shape lies within FIELD_RADIUS * size of the cell's vertical axis, at y >= lift >= 0.
float fieldShape(vec3 q, float i, float j, float size, FieldPose pose) {
    float s = max(size, 0.05f) * FIELD_UNIT;
    float lift = pose.lift;
    float kind = mod(i + 3.0f * j + floor(0.5f * i), 4.0f);
    float d;
    if (kind < 0.5f) {
        d = fSphere(pTranslate(q, vec3(0.0f, 0.36f * s + lift, 0.0f)), 0.36f * s);   // r 0.36
    } else if (kind < 1.5f) {
        vec3 b = fieldTurnY(pTranslate(q, vec3(0.0f, 0.30f * s + lift, 0.0f)), pose.turn);
        d = fRoundBox(b, vec3(0.26f, 0.30f, 0.26f) * s, 0.06f * s);                 // corner 0.368
    } else if (kind < 2.5f) {
        vec3 t = fieldTurnY(pTranslate(q, vec3(0.0f, 0.38f * s + lift, 0.0f)), pose.turn);
        d = fTorus(pRotateX(t, 0.5f * PI), 0.11f * s, 0.27f * s);                   // outer 0.38
    } else {
        vec3 a = vec3(0.0f, 0.2f * s + lift, 0.0f);
        vec3 tip = vec3(0.165f * pose.turn.x, 0.525f, 0.165f * pose.turn.y) * s;    // 0.55 long, tilted
        d = fCapsule(q, a, a + tip, 0.2f * s);                                      // 0.165 + 0.2
    }
    return d;
}

// Complex product: the sum of two angles given as (cos, sin).
vec2 fieldAngleAdd(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

// The poses of the 2x2 cells (i0 + a, j0 + b): lifts by a + b (the wave runs along i + j), turns
// by corner. Two sin/cos pairs and angle additions instead of three trigonometric calls per
// cell (on the GPU the field's map() cost was mostly those); the same values to rounding
// (tests/sdf: against fieldMapAll, which takes fieldPose per cell).
struct FieldBlock {
    vec3 lift;                       // a + b = 0, 1, 2
    vec2 turn00, turn10, turn01, turn11;
};

FieldBlock fieldBlockPoses(float i0, float j0, float wave, float phase, float spin) {
    // (cos, sin) of one and two wave steps, of the turn steps along i, j and both
    const vec2 k055 = vec2(cos(FIELD_WAVE_STEP), sin(FIELD_WAVE_STEP));
    const vec2 k110 = vec2(cos(2.0f * FIELD_WAVE_STEP), sin(2.0f * FIELD_WAVE_STEP));
    const vec2 k090 = vec2(cos(FIELD_TURN_I), sin(FIELD_TURN_I));
    const vec2 k040 = vec2(cos(FIELD_TURN_J), sin(FIELD_TURN_J));
    const vec2 k130 = vec2(cos(FIELD_TURN_I + FIELD_TURN_J), sin(FIELD_TURN_I + FIELD_TURN_J));
    float x = phase - FIELD_WAVE_STEP * (i0 + j0);
    vec2 w = vec2(cos(x), sin(x));
    // sin(x - c) = sin x cos c - cos x sin c
    vec3 sines = vec3(w.y, w.y * k055.x - w.x * k055.y, w.y * k110.x - w.x * k110.y);
    FieldBlock k;
    k.lift = wave * (0.5f + 0.5f * sines);
    float base = fieldTurn(i0, j0, spin);   // corner (0, 0); its diagonal neighbour spins the same way
    vec2 t = vec2(cos(base), sin(base));
    // the other two spin the other way: base - 2 sigma spin + a step along i or j (sigma = +-1, corner
    // (0, 0)'s direction; sin/cos of 2 spin are the same for every pixel)
    float sigma = mod(i0 + j0, 2.0f) < 0.5f ? 1.0f : -1.0f;
    vec2 u = fieldAngleAdd(t, vec2(cos(2.0f * spin), -sigma * sin(2.0f * spin)));
    k.turn00 = t;
    k.turn11 = fieldAngleAdd(t, k130);
    k.turn10 = fieldAngleAdd(u, k090);
    k.turn01 = fieldAngleAdd(u, k040);
    return k;
}

FieldPose fieldBlockPose(FieldBlock k, float a, float b) {
    float lift = a + b < 0.5f ? k.lift.x : (a + b < 1.5f ? k.lift.y : k.lift.z);
    vec2 turn = a < 0.5f ? (b < 0.5f ? k.turn00 : k.turn01) : (b < 0.5f ? k.turn10 : k.turn11);
    return FieldPose(lift, turn);
}

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

// Inserts cell (i, j)'s shape at p into the pair. Skips the shape (exactly) when the cylinder
// around it is no nearer than the pair's second, and cells outside the nx x nz grid.
FieldPair fieldCell(FieldPair n, vec3 p, float i, float j, float nx, float nz, float size, FieldPose pose) {
    if (i < -0.5f || j < -0.5f || i > nx - 0.5f || j > nz - 0.5f) return n;
    vec3 q = p - vec3(i - 0.5f * (nx - 1.0f), 0.0f, j - 0.5f * (nz - 1.0f));
    if (length(vec2(q.x, q.z)) - FIELD_RADIUS * max(size, 0.05f) >= n.next.w) return n;
    return fieldInsert(n, vec4(i, j, 0.0f, fieldShape(q, i, j, size, pose)));
}

// The pair's blend with its colours.
vec4 fieldBlend(FieldPair n, float blend) {
    vec3 a = fieldColor(n.near.x, n.near.y);
    vec3 b = n.next.w < 1e8f ? fieldColor(n.next.x, n.next.y) : a;
    return fOpUnionSmoothColor(vec4(a.x, a.y, a.z, n.near.w), vec4(b.x, b.y, b.z, n.next.w), blend);
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
    return max(gap, fieldGridDistance(u, v, nx, nz)) - FIELD_RADIUS * max(size, 0.05f);
}

// The field of nx x nz shapes at p: four shapes evaluated, exact within the blend radius.
vec4 fieldMap(vec3 p, float nx, float nz, float size, float blend, float wave, float phase, float spin) {
    float u = p.x + 0.5f * (nx - 1.0f);   // cell coordinates: cell (i, j)'s centre at (u, v) = (i, j)
    float v = p.z + 0.5f * (nz - 1.0f);
    float i0 = clamp(floor(u), 0.0f, nx - 2.0f);
    float j0 = clamp(floor(v), 0.0f, nz - 2.0f);
    // nearest centre first, so the cylinder test skips more of the others
    float di = u - i0 < 0.5f ? 0.0f : 1.0f;
    float dj = v - j0 < 0.5f ? 0.0f : 1.0f;
    FieldBlock poses = fieldBlockPoses(i0, j0, wave, phase, spin);
    FieldPair n = FieldPair(vec4(0.0f, 0.0f, 0.0f, 1e9f), vec4(0.0f, 0.0f, 0.0f, 1e9f));
    n = fieldCell(n, p, i0 + di, j0 + dj, nx, nz, size, fieldBlockPose(poses, di, dj));
    n = fieldCell(n, p, i0 + 1.0f - di, j0 + dj, nx, nz, size, fieldBlockPose(poses, 1.0f - di, dj));
    n = fieldCell(n, p, i0 + di, j0 + 1.0f - dj, nx, nz, size, fieldBlockPose(poses, di, 1.0f - dj));
    n = fieldCell(n, p, i0 + 1.0f - di, j0 + 1.0f - dj, nx, nz, size, fieldBlockPose(poses, 1.0f - di, 1.0f - dj));
    vec4 m = fieldBlend(n, blend);
    float k = max(blend, 0.0f);
    m.w = min(m.w, max(fieldExcluded(u, v, i0, j0, nx, nz, size) - 1.25f * k, p.y - fieldTop(size, wave) - 0.25f * k));
    return m;
}

// The reference: the same field over every shape (nx * nz evaluations). Tests only.
vec4 fieldMapAll(vec3 p, float nx, float nz, float size, float blend, float wave, float phase, float spin) {
    FieldPair n = FieldPair(vec4(0.0f, 0.0f, 0.0f, 1e9f), vec4(0.0f, 0.0f, 0.0f, 1e9f));
    for (int j = 0; j < int(nz); j++)
        for (int i = 0; i < int(nx); i++) {
            vec3 q = p - vec3(float(i) - 0.5f * (nx - 1.0f), 0.0f, float(j) - 0.5f * (nz - 1.0f));
            FieldPose pose = fieldPose(float(i), float(j), wave, phase, spin);
            n = fieldInsert(n, vec4(float(i), float(j), 0.0f, fieldShape(q, float(i), float(j), size, pose)));
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
