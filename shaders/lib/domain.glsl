// domain.glsl - domain operators: they map the sample point before a primitive sees it.
//
// Usage (the subset has no inout: operators return the new point, or a small struct):
//     vec3 q = pRotateY(pTranslate(p, centre), angle);
//     q = pTwistY(q, k);              // then sceneLipschitz() must include lipschitzTwist(k, R)
//     Mod1 m = pMod1(q.x, 2.0f);      // m.p: point inside the cell, m.cell: cell index
//     vec3 s = pScale(q, 0.5f);  float d = fOpScale(fBox(s, b), 0.5f);
// Rigid transforms keep a field exact; twist, bend and displacement inflate its gradient:
// the lipschitzX() helpers give the factor to report from sceneLipschitz().
#ifndef SDF_LIB_DOMAIN_GLSL
#define SDF_LIB_DOMAIN_GLSL
#include "lib/common.glsl"

// ---- rigid transforms --------------------------------------------------------------
vec3 pTranslate(vec3 p, vec3 offset) { return p - offset; }

// Rotation matrices (right-handed, angle in radians) that rotate a vector by `a`.
mat3 rotationX(float a) {
    float c = cos(a);
    float s = sin(a);
    return mat3(1.0f, 0.0f, 0.0f, 0.0f, c, s, 0.0f, -s, c);
}
mat3 rotationY(float a) {
    float c = cos(a);
    float s = sin(a);
    return mat3(c, 0.0f, -s, 0.0f, 1.0f, 0.0f, s, 0.0f, c);
}
mat3 rotationZ(float a) {
    float c = cos(a);
    float s = sin(a);
    return mat3(c, s, 0.0f, -s, c, 0.0f, 0.0f, 0.0f, 1.0f);
}

// Rotate the OBJECT by `a` around the axis (the point is rotated by -a). Exact.
vec3 pRotateX(vec3 p, float a) { return rotationX(-a) * p; }
vec3 pRotateY(vec3 p, float a) { return rotationY(-a) * p; }
vec3 pRotateZ(vec3 p, float a) { return rotationZ(-a) * p; }
// pRotateY by the angle whose cosine and sine are c and s.
vec3 pRotateYcs(vec3 p, float c, float s) { return mat3(c, 0.0f, s, 0.0f, 1.0f, 0.0f, -s, 0.0f, c) * p; }
// Rotate the object by the rotation matrix m (orthonormal).
vec3 pRotate(vec3 p, mat3 m) { return transpose(m) * p; }

// ---- uniform scale -----------------------------------------------------------------
// Scale near 0 is guarded (|s| >= 1e-4) identically in both halves.
float scaleGuard(float s) { return sgn(s) * max(abs(s), 1e-4f); }
// Scale the object by s: sample the primitive at pScale(p, s) and multiply its distance
// back with fOpScale(d, s). The pair keeps the field exact.
vec3 pScale(vec3 p, float s) { return p / scaleGuard(s); }
float fOpScale(float d, float s) { return d * abs(scaleGuard(s)); }

// ---- twist and bend (not distance preserving) ---------------------------------------
// Twist around the axis: the plane perpendicular to it is rotated by k * (coordinate
// along the axis) radians. For points within radius R of the axis the gradient grows by
// at most lipschitzTwist(k, R).
vec3 pTwistX(vec3 p, float k) {
    float c = cos(k * p.x);
    float s = sin(k * p.x);
    return vec3(p.x, c * p.y - s * p.z, s * p.y + c * p.z);
}
vec3 pTwistY(vec3 p, float k) {
    float c = cos(k * p.y);
    float s = sin(k * p.y);
    return vec3(c * p.x - s * p.z, p.y, s * p.x + c * p.z);
}
vec3 pTwistZ(vec3 p, float k) {
    float c = cos(k * p.z);
    float s = sin(k * p.z);
    return vec3(c * p.x - s * p.y, s * p.x + c * p.y, p.z);
}
// Largest singular value of the twist's Jacobian at radius R: the shear k*R gives
// (s + sqrt(s^2 + 4)) / 2, slightly more than the often quoted sqrt(1 + s^2).
float lipschitzTwist(float k, float radius) {
    float s = abs(k) * radius;
    return 0.5f * (s + sqrt(s * s + 4.0f));
}

// Bend in the XY plane: the XY plane is rotated by k * x (a straight bar along X bends
// into an arc). For points within R of the Z axis the gradient grows by at most
// lipschitzBend(k, R) = 1 + |k| R (more than a twist: the angle depends on a coordinate
// that the rotation itself moves).
vec3 pBend(vec3 p, float k) {
    float c = cos(k * p.x);
    float s = sin(k * p.x);
    return vec3(c * p.x - s * p.y, s * p.x + c * p.y, p.z);
}
float lipschitzBend(float k, float radius) {
    return 1.0f + abs(k) * radius;
}

// ---- displacement ---------------------------------------------------------------------
// Sinusoidal displacement added to a distance: d + fDisplacement(p, a, f).
// Adds lipschitzDisplacement(a, f) = |a * f| to the gradient bound.
float fDisplacement(vec3 p, float amplitude, float frequency) {
    return amplitude * sin(frequency * p.x) * sin(frequency * p.y) * sin(frequency * p.z);
}
float lipschitzDisplacement(float amplitude, float frequency) {
    return abs(amplitude * frequency);
}
// Sinusoidal domain warp: each axis is pushed by a sine of another one.
// Gradient factor at most lipschitzDisplace(a, f) = 1 + |a * f|.
vec3 pDisplace(vec3 p, float amplitude, float frequency) {
    return p + amplitude * vec3(sin(frequency * p.y), sin(frequency * p.z), sin(frequency * p.x));
}
float lipschitzDisplace(float amplitude, float frequency) {
    return 1.0f + abs(amplitude * frequency);
}

// ---- repetition ---------------------------------------------------------------------
// Results of the repetition operators: the point inside its cell and the cell index.
struct Mod1 { float p; float cell; };
struct Mod2 { vec2 p; vec2 cell; };
struct Mod3 { vec3 p; vec3 cell; };

// Repeat along one axis every `size` units; cell 0 is centred on 0. Exact if the repeated
// shape fits in its cell.
Mod1 pMod1(float p, float size) {
    float s = max(abs(size), 1e-4f);
    float h = 0.5f * s;
    return Mod1(mod(p + h, s) - h, floor((p + h) / s));
}

// Repeat only on the positive side: p < -size/2 stays in cell 0 untouched.
Mod1 pModPositive1(float p, float size) {
    float s = max(abs(size), 1e-4f);
    float h = 0.5f * s;
    float c = max(floor((p + h) / s), 0.0f);
    return Mod1(p - c * s, c);
}

// Repeat only cells start..stop (inclusive); beyond them the end cells extend.
Mod1 pModInterval1(float p, float size, float start, float stop) {
    float s = max(abs(size), 1e-4f);
    float h = 0.5f * s;
    float c = clamp(floor((p + h) / s), start, stop);
    return Mod1(p - c * s, c);
}

// Repeat on a 2D / 3D grid.
Mod2 pMod2(vec2 p, vec2 size) {
    vec2 s = max(abs(size), 1e-4f);
    vec2 h = 0.5f * s;
    return Mod2(mod(p + h, s) - h, floor((p + h) / s));
}
Mod3 pMod3(vec3 p, vec3 size) {
    vec3 s = max(abs(size), 1e-4f);
    vec3 h = 0.5f * s;
    return Mod3(mod(p + h, s) - h, floor((p + h) / s));
}

// ---- symmetry -----------------------------------------------------------------------
// Mirror at the plane coordinate = dist: p becomes |p - dist| (one side folds onto the
// other); side is -1 for points that were on the negative side, else +1.
struct Mirror1 { float p; float side; };
Mirror1 pMirror(float p, float dist) {
    return Mirror1(abs(p - dist), sgn(p - dist));
}
// Mirror the whole point at the YZ plane (x -> |x|): left/right symmetric models.
vec3 pMirrorX(vec3 p) { return vec3(abs(p.x), p.y, p.z); }

#endif
