// mandelbulb.glsl - distance estimator of the Mandelbulb fractal (power-n "triplex" Julia
// iteration z -> z^n + p), with a bounding sphere for distant samples.
//
// Usage: float d = fMandelbulb(p, 8.0f, 8);             // distance bound
//        vec2 dt = fMandelbulbTrap(p, power, iterations); // (distance, orbit trap in [0,1])
// The estimate 0.5 * log(r) * r / dr is not a strict bound near the surface; scenes
// usually claim sceneLipschitz() a little above 1. Guarded at r = 0 (the origin is inside
// the set: the estimate is a small negative number there, never NaN).
#ifndef SDF_LIB_MANDELBULB_GLSL
#define SDF_LIB_MANDELBULB_GLSL
#include "lib/common.glsl"

// Radius of a sphere that contains the Mandelbulb of the given power: points with
// |p| > 2^(1/(n-1)) escape, plus a small margin.
float mandelbulbBoundingRadius(float power) {
    return pow(2.0f, 1.0f / max(power - 1.0f, 1.0f)) + 0.05f;
}

vec2 mandelbulbComplexMul(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }

// The triplex power z^n for a whole n (1..15) with r = |z|, and r^(n-1) in w, with no
// trigonometry (iq's observation for n = 8, by squaring for any n): with rho = |z.xz|,
// (z.y + i rho)^n = r^n (cos n theta, sin n theta) and ((z.x + i z.z) / rho)^n =
// (cos n phi, sin n phi), the same angles the general loop takes from acos and atan. On the
// y axis (rho = 0) phi is taken as 0, as atan(0, 0) gives in the C++ reference.
// MANDELBULB_FEW_SFU (on): rho and 1 / rho from one inversesqrt, and r^(n-1) by the same
// squarings (the bits of n - 1) instead of r^n / r: two special-function operations an iteration
// (a square root and a reciprocal) fewer, the same values up to rounding. On llvmpipe, where those
// are ordinary vector instructions, it measured 2.5 % slower (320x180, full lighting); on the
// NVIDIA H200, whose special-function unit runs at a fraction of its FMA rate, 3.7-3.8 % faster in
// full lighting at 1080p and 4K and 6.0 % in the 7680x4320 show (11.82 -> 11.10 ms; one
// interleaved run, docs/performance.md, "Session 29"). 0: r^n / r and a division by rho.
#ifndef MANDELBULB_FEW_SFU
#define MANDELBULB_FEW_SFU 1
#endif
vec4 mandelbulbPowInt(vec3 z, float r, int n) {
#if MANDELBULB_FEW_SFU
    float rho2 = z.x * z.x + z.z * z.z;
    float invRho = rho2 > 0.0f ? inversesqrt(rho2) : 0.0f;
    vec2 a = vec2(z.y, rho2 * invRho);
    vec2 b = rho2 > 0.0f ? vec2(z.x, z.z) * invRho : vec2(1.0f, 0.0f);
#else
    float rho = length(vec2(z.x, z.z));
    vec2 a = vec2(z.y, rho);
    vec2 b = rho > 0.0f ? vec2(z.x, z.z) / rho : vec2(1.0f, 0.0f);
#endif
    vec2 an = vec2(1.0f, 0.0f);
    vec2 bn = vec2(1.0f, 0.0f);
    float rn = 1.0f;   // r^n, or r^(n-1) with MANDELBULB_FEW_SFU
    float rk = r;
    // n's four bits, lowest first: a fixed loop the compilers unroll, its tests uniform
    for (int k = 0; k < 4; k++) {
        if (((n >> k) & 1) != 0) {
            an = mandelbulbComplexMul(an, a);
            bn = mandelbulbComplexMul(bn, b);
        }
#if MANDELBULB_FEW_SFU
        if ((((n - 1) >> k) & 1) != 0) rn *= rk;
#else
        if (((n >> k) & 1) != 0) rn *= rk;
#endif
        a = mandelbulbComplexMul(a, a);
        b = mandelbulbComplexMul(b, b);
        rk *= rk;
    }
#if MANDELBULB_FEW_SFU
    return vec4(an.y * bn.x, an.x, an.y * bn.y, rn);
#else
    return vec4(an.y * bn.x, an.x, an.y * bn.y, r > 0.0f ? rn / r : 0.0f);
#endif
}

// The same power through acos, atan and pow, for any real n >= 2: (z^n, r^(n-1)).
vec4 mandelbulbPowTrig(vec3 z, float r, float n) {
    // z = 0: z^n = 0 and the angles are undefined (atan(0, 0)).
    if (r < 1e-12f) return vec4(0.0f, 0.0f, 0.0f, pow(r, n - 1.0f));
    float theta = acos(clamp(z.y / r, -1.0f, 1.0f)) * n;
    float phi = atan(z.z, z.x) * n;
    float zr = pow(r, n);
    float st = sin(theta);
    return vec4(zr * vec3(st * cos(phi), cos(theta), st * sin(phi)), pow(r, n - 1.0f));
}

// The orbit of p (eight: n is 8, taken by mandelbulbPowInt, else mandelbulbPowTrig; boundR:
// mandelbulbBoundingRadius(n)): (distance estimate, orbit trap). Far from the fractal the bounding sphere's distance is returned
// instead: a valid, cheap, well-conditioned bound (the estimator over-steps badly out there).
// One loop per step, the whole step only for n = 8 (the default and the presets) with the power
// a constant: a branch inside the loop, or a power known only at run time, cost llvmpipe (8
// pixels in lockstep) more than the trigonometry saved (docs/performance.md).
#define MANDELBULB_STEP(POW)                          \
    for (int i = 0; i < iterations; i++) {            \
        float r = length(z);                          \
        if (r > 2.0f) break;                          \
        vec4 zn = POW;                                \
        dr = n * zn.w * dr + 1.0f;                    \
        z = vec3(zn.x, zn.y, zn.z) + p;               \
        trap = min(trap, dot(z, z));                  \
    }
vec2 mandelbulbOrbit(vec3 p, float n, int iterations, bool eight, float boundR) {
    float rp = length(p);
    if (rp > boundR + 0.1f) return vec2(rp - boundR, 1.0f);
    vec3 z = p;
    float dr = 1.0f;
    float trap = 1e10f;
    if (eight) {
        MANDELBULB_STEP(mandelbulbPowInt(z, r, 8))
    } else {
        MANDELBULB_STEP(mandelbulbPowTrig(z, r, n))
    }
    float r = max(length(z), 1e-12f);
    return vec2(0.5f * log(r) * r / dr, clamp(trap, 0.0f, 1.0f));
}
#undef MANDELBULB_STEP

// (distance estimate, orbit trap): the trap is the smallest |z|^2 seen by the orbit,
// clamped to [0, 1]; scenes map it to colour or occlusion. Power 8 (the default, and the
// presets') takes the step without trigonometry; the choice is the same for every pixel, so a
// GPU warp never diverges on it.
// boundR: mandelbulbBoundingRadius(max(power, 2)), which a scene may compute once per invocation.
vec2 fMandelbulbTrapBounded(vec3 p, float power, int iterations, float boundR) {
    float n = max(power, 2.0f);
    return mandelbulbOrbit(p, n, iterations, n == 8.0f, boundR);
}
vec2 fMandelbulbTrap(vec3 p, float power, int iterations) {
    return fMandelbulbTrapBounded(p, power, iterations, mandelbulbBoundingRadius(max(power, 2.0f)));
}

// Distance estimate only.
float fMandelbulb(vec3 p, float power, int iterations) {
    return fMandelbulbTrap(p, power, iterations).x;
}

#endif
