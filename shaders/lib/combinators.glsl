// combinators.glsl - combine two distances: union, intersection, subtraction, their
// smooth forms, and colour-carrying versions on vec4(albedo.r, albedo.g, albedo.b, dist).
//
// Usage: float d = fOpUnionSmooth(fSphere(p, 1.0f), fBox(p - c, b), 0.3f);
//        vec4 m = fOpUnionSmoothColor(vec4(red, dSphere), vec4(blue, dBox), 0.3f);
// k is the blend radius in distance units (how far apart two surfaces may be and still
// blend). k <= 0 is guarded everywhere and gives the sharp operator. The polynomial and
// cubic smooth minima keep a 1-Lipschitz field 1-Lipschitz, so they need no step-factor
// correction.
#ifndef SDF_LIB_COMBINATORS_GLSL
#define SDF_LIB_COMBINATORS_GLSL
#include "lib/common.glsl"

// ---- sharp --------------------------------------------------------------------------
float fOpUnion(float a, float b) { return min(a, b); }
float fOpIntersection(float a, float b) { return max(a, b); }
// a with b carved out of it
float fOpSubtraction(float a, float b) { return max(a, -b); }

// ---- smooth minima ------------------------------------------------------------------
// Polynomial (quadratic): C1, lowers the result by at most k/4 where |a - b| < k.
float sminPoly(float a, float b, float k) {
    if (k <= 1e-6f) return min(a, b);
    float h = max(k - abs(a - b), 0.0f) / k;
    return min(a, b) - h * h * k * 0.25f;
}

// Cubic: C2, lowers the result by at most k/6 where |a - b| < k.
float sminCubic(float a, float b, float k) {
    if (k <= 1e-6f) return min(a, b);
    float h = max(k - abs(a - b), 0.0f) / k;
    return min(a, b) - h * h * h * k * (1.0f / 6.0f);
}

// Exponential: infinitely smooth, lowers the result by up to k (never exactly min, even
// far apart). Written relative to min(a, b) so exp2 only sees exponents <= 0: no overflow
// for huge distances or tiny k, and the log argument stays in [1, 2].
float sminExp(float a, float b, float k) {
    if (k <= 1e-6f) return min(a, b);
    float m = min(a, b);
    float s = exp2(-(a - m) / k) + exp2(-(b - m) / k);
    return m - k * log2(s);
}

// Power: for positive distances only (falls back to min otherwise); larger k is sharper
// (k -> infinity gives min). Written as m * (1 + (m/M)^k)^(-1/k) so no power overflows.
float sminPow(float a, float b, float k) {
    if (a <= 0.0f || b <= 0.0f) return min(a, b);
    float kk = max(k, 1e-2f);
    float m = min(a, b);
    float big = max(a, b);
    return m * pow(1.0f + pow(m / big, kk), -1.0f / kk);
}

// Smooth maximum from the polynomial smooth minimum.
float smaxPoly(float a, float b, float k) { return -sminPoly(-a, -b, k); }

// ---- smooth operators -------------------------------------------------------------
float fOpUnionSmooth(float a, float b, float k) { return sminPoly(a, b, k); }
float fOpIntersectionSmooth(float a, float b, float k) { return smaxPoly(a, b, k); }
float fOpSubtractionSmooth(float a, float b, float k) { return smaxPoly(a, -b, k); }

// ---- colour-carrying versions: vec4(albedo.rgb, distance) --------------------------
vec3 albedoOf(vec4 m) { return vec3(m.x, m.y, m.z); }

vec4 fOpUnionColor(vec4 a, vec4 b) { return a.w < b.w ? a : b; }
vec4 fOpIntersectionColor(vec4 a, vec4 b) { return a.w > b.w ? a : b; }
// keeps a's colour where a survives, b's colour on the carved faces
vec4 fOpSubtractionColor(vec4 a, vec4 b) { return a.w > -b.w ? a : vec4(albedoOf(b), -b.w); }

// Weight of `a` in the polynomial blend (1 = all a), guarded at k = 0.
float blendWeight(float a, float b, float k) {
    if (k <= 1e-6f) return a < b ? 1.0f : 0.0f;
    return clamp(0.5f + 0.5f * (b - a) / k, 0.0f, 1.0f);
}

// Smooth union; colours blend across the same region as the distances.
vec4 fOpUnionSmoothColor(vec4 a, vec4 b, float k) {
    float h = blendWeight(a.w, b.w, k);
    return vec4(mix(albedoOf(b), albedoOf(a), h), sminPoly(a.w, b.w, k));
}
// The same with 1 / k given (invK = smoothInv(k): 1 / k, or 0 where k <= 1e-6 and the operator is
// sharp): no division and no branch in the call. For a k the frame fixes: a scene's setup computes
// smoothInv(k) once (the fields, lib/field_scene.glsl). Equal to sminPoly / fOpUnionSmoothColor
// but for the division's last bit.
float smoothInv(float k) { return k > 1e-6f ? 1.0f / k : 0.0f; }
float sminPolyInv(float a, float b, float k, float invK) {
    float h = max(k - abs(a - b), 0.0f) * invK;
    return min(a, b) - h * h * k * 0.25f;
}
vec4 fOpUnionSmoothColorInv(vec4 a, vec4 b, float k, float invK) {
    float h = invK > 0.0f ? clamp(0.5f + 0.5f * (b.w - a.w) * invK, 0.0f, 1.0f) : (a.w < b.w ? 1.0f : 0.0f);
    return vec4(mix(albedoOf(b), albedoOf(a), h), sminPolyInv(a.w, b.w, k, invK));
}
vec4 fOpIntersectionSmoothColor(vec4 a, vec4 b, float k) {
    float h = blendWeight(-a.w, -b.w, k);
    return vec4(mix(albedoOf(b), albedoOf(a), h), smaxPoly(a.w, b.w, k));
}
// a minus b; the carved faces take b's colour, blended over the rounded edge
vec4 fOpSubtractionSmoothColor(vec4 a, vec4 b, float k) {
    float h = blendWeight(-a.w, b.w, k);
    return vec4(mix(albedoOf(b), albedoOf(a), h), smaxPoly(a.w, -b.w, k));
}

#endif
