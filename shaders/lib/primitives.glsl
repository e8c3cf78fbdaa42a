// primitives.glsl - signed distance functions of basic shapes, centred at the origin.
//
// Usage: float d = fBox(p - centre, vec3(1.0f, 0.5f, 0.5f));
// Every fX(p, ...) returns a signed distance (negative inside) that is either exact or a
// lower bound of the true distance (|grad| <= 1), as noted per function. Axis-aligned
// shapes use +Y as "up"; move/rotate them with the operators in domain.glsl.
#ifndef SDF_LIB_PRIMITIVES_GLSL
#define SDF_LIB_PRIMITIVES_GLSL
#include "lib/common.glsl"

// Plane through the point n * -distanceFromOrigin, normal n (unit length). Exact.
float fPlane(vec3 p, vec3 n, float distanceFromOrigin) {
    return dot(p, n) + distanceFromOrigin;
}

// Sphere of radius r. Exact.
float fSphere(vec3 p, float r) {
    return length(p) - r;
}

// Box with half-extents b. Exact.
float fBox(vec3 p, vec3 b) {
    vec3 q = abs(p) - b;
    return length(max(q, 0.0f)) + min(vmax(q), 0.0f);
}

// Box with half-extents b and edges rounded by radius r (r <= min(b)). Exact.
float fRoundBox(vec3 p, vec3 b, float r) {
    return fBox(p, b - r) - r;
}

// Ellipsoid with semi-axes r. A bound, not exact: length(p/r) scaled so |grad| <= 1.
// Guarded at the origin (and at the centre of a very flat ellipsoid) where the gradient
// term vanishes.
float fEllipsoid(vec3 p, vec3 r) {
    float k0 = length(p / r);
    float k1 = length(p / (r * r));
    // Near the centre k1 -> 0: fall back to the (always valid) inscribed-sphere bound.
    if (k1 < 1e-6f) return -vmin(r);
    return max(k0 * (k0 - 1.0f) / k1, (k0 - 1.0f) * vmin(r));
}

// Capped cylinder around the Y axis: radius r, half-height h. Exact.
float fCylinder(vec3 p, float r, float h) {
    vec2 d = vec2(length(vec2(p.x, p.z)) - r, abs(p.y) - h);
    return min(max(d.x, d.y), 0.0f) + length(max(d, 0.0f));
}

// Capsule: all points within r of the segment a-b (a == b gives a sphere). Exact.
float fCapsule(vec3 p, vec3 a, vec3 b, float r) {
    vec3 pa = p - a;
    vec3 ba = b - a;
    float h = clamp(dot(pa, ba) / max(dot(ba, ba), 1e-12f), 0.0f, 1.0f);
    return length(pa - ba * h) - r;
}
// The same with invLen2 = 1 / max(|b - a|^2, 1e-12) given (capsuleInvLen2: a scene computes it once
// per frame for a capsule whose ends are the frame's): no division per call.
float capsuleInvLen2(vec3 a, vec3 b) { vec3 ba = b - a; return 1.0f / max(dot(ba, ba), 1e-12f); }
float fCapsuleInv(vec3 p, vec3 a, vec3 b, float r, float invLen2) {
    vec3 pa = p - a;
    vec3 ba = b - a;
    float h = clamp(dot(pa, ba) * invLen2, 0.0f, 1.0f);
    return length(pa - ba * h) - r;
}

// Torus in the XZ plane: tube radius smallRadius, ring radius largeRadius. Exact.
float fTorus(vec3 p, float smallRadius, float largeRadius) {
    return length(vec2(length(vec2(p.x, p.z)) - largeRadius, p.y)) - smallRadius;
}

// 2D distance to an equilateral triangle in the XY plane, centred at the origin, apex
// up (+Y), with inradius (centre-to-edge distance) h. Exact.
float fTriangle2D(vec2 p, float h) {
    float halfSide = h * SQRT3;
    float x = abs(p.x) - halfSide;
    float y = p.y + h;
    // fold the point across the right edge's normal so one edge test covers all three
    if (x + SQRT3 * y > 0.0f) {
        float nx = (x - SQRT3 * y) * 0.5f;
        float ny = (-SQRT3 * x - y) * 0.5f;
        x = nx;
        y = ny;
    }
    x -= clamp(x, -2.0f * halfSide, 0.0f);
    float l = length(vec2(x, y));
    return y > 0.0f ? -l : l;
}

// Extrude a 2D distance d along Z to half-length h (exact if d is exact).
float fExtrude(vec3 p, float d, float h) {
    vec2 w = vec2(d, abs(p.z) - h);
    return min(max(w.x, w.y), 0.0f) + length(max(w, 0.0f));
}

// Triangular prism along Z: equilateral triangle (apex +Y, inradius h.x) extruded to
// half-length h.y. Exact.
float fTriPrism(vec3 p, vec2 h) {
    return fExtrude(p, fTriangle2D(vec2(p.x, p.y), h.x), h.y);
}

// Hexagonal prism along Z: regular hexagon with flat top/bottom, apothem (centre-to-side
// distance) h.x, extruded to half-length h.y. Exact.
float fHexPrism(vec3 p, vec2 h) {
    // k = (-cos 30, sin 30, tan 30)
    float kx = -0.5f * SQRT3;
    float ky = 0.5f;
    float kz = 1.0f / SQRT3;
    float x = abs(p.x);
    float y = abs(p.y);
    float f = 2.0f * min(kx * x + ky * y, 0.0f);
    x -= f * kx;
    y -= f * ky;
    float e = length(vec2(x - clamp(x, -kz * h.x, kz * h.x), y - h.x)) * sgn(y - h.x);
    return fExtrude(p, e, h.y);
}

// Rounding: turn the surface at distance r outside d into the new surface. fOpRound(fBox(p,
// b), r) grows the box by r with rounded edges. Exact if d is exact.
float fOpRound(float d, float r) {
    return d - r;
}

// Onion: a shell of the given half-thickness around the surface of d. Exact if d is exact.
float fOpOnion(float d, float thickness) {
    return abs(d) - thickness;
}

#endif
