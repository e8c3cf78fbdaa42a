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

// (distance estimate, orbit trap): the trap is the smallest |z|^2 seen by the orbit,
// clamped to [0, 1]; scenes map it to colour or occlusion.
vec2 fMandelbulbTrap(vec3 p, float power, int iterations) {
    float n = max(power, 2.0f);
    float boundR = mandelbulbBoundingRadius(n);
    float rp = length(p);
    // Bounding-sphere trick: far from the fractal the sphere's distance is a valid, cheap,
    // well-conditioned bound (the estimator over-steps badly out there).
    if (rp > boundR + 0.1f) return vec2(rp - boundR, 1.0f);

    vec3 z = p;
    float dr = 1.0f;
    float r = rp;
    float trap = 1e10f;
    for (int i = 0; i < iterations; i++) {
        r = length(z);
        if (r > 2.0f) break;
        dr = n * pow(r, n - 1.0f) * dr + 1.0f;
        if (r < 1e-12f) {
            // z = 0: z^n = 0 and the angles are undefined (atan(0, 0)); next z is p.
            z = p;
        } else {
            float theta = acos(clamp(z.y / r, -1.0f, 1.0f)) * n;
            float phi = atan(z.z, z.x) * n;
            float zr = pow(r, n);
            float st = sin(theta);
            z = zr * vec3(st * cos(phi), cos(theta), st * sin(phi)) + p;
        }
        trap = min(trap, dot(z, z));
    }
    r = max(length(z), 1e-12f);
    float d = 0.5f * log(r) * r / dr;
    return vec2(d, clamp(trap, 0.0f, 1.0f));
}

// Distance estimate only.
float fMandelbulb(vec3 p, float power, int iterations) {
    return fMandelbulbTrap(p, power, iterations).x;
}

#endif
