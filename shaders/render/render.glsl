// render.glsl - the raymarcher and shader body shared by the fragment and compute paths.
//
// The host includes it after render/uniforms.glsl, the scene's `uniform float u_<input>;`
// lines and the scene (which defines `vec4 map(vec3 p)` and `float sceneLipschitz()`).
// It defines `vec4 render(vec2 fragCoord)`: fragCoord in pixels (pixel centres at +0.5,
// origin bottom-left as gl_FragCoord), returns the display colour (tone mapped, sRGB,
// alpha 1). Written in the GLSL/C++ subset, so the CPU reference renderer runs it too.
//
// Compile-time switches (the host emits #defines; 0 compiles the effect out entirely):
//   SHADOWS     0 none / 1 hard / 2 soft / 3 improved soft
//   AO          0 / 1            SPECULAR  0 / 1 (Blinn-Phong)
//   PBR         0 / 1 (Cook-Torrance replaces Lambert + Blinn-Phong)
//   REFLECTIONS number of mirror bounces (0 = none)
//   FOG         0 / 1 (distance fog + sky background)
//   DEBUG_VIEW  0 shaded / 1 step-count heatmap / 2 depth / 3 normals
//               4 geometry for the accuracy bench (float target): vec4(t or -1 on a miss,
//                 octahedral normal x, y, steps + 0.5 if the ray ran out of steps)
//               5 linear radiance before tone mapping (float target; NaN/Inf scans)
//               6, 7 where the pixel's map() calls went (float target; `sdfvj bench work`): 6 the
//                 primary ray's march, normal, shadow ray and AO; 7 the same for its reflection
//               8 all of them as a heatmap (effect `work`: 0 calls blue .. 127 or more red, log scale)
//   NORMALS     0 central / 1 forward / 2 tetrahedron differences
//   MARCH_FIXED 0 sphere tracing / 1 fixed step of u_fixedStep
//   EPS_MODE    hit threshold: 0 u_hitEps * max(1, t) / 1 fixed u_hitEps /
//               2 u_hitEps pixel footprints (u_hitEps * t * pixel angle)
//   BOUNCE_STEPS a reflection ray's step budget (0: u_maxSteps, as the primary ray's)
//   BOUNCE_LIGHT what lights the surface a reflection meets: 0 as a primary hit (shadows, AO) /
//               1 no AO / 2 neither shadow nor AO (direct light unshadowed, ambient unoccluded)
//   BOUNCE_BOUND N (default 4; 0 off): a reflection's shadow ray and AO are skipped where no
//               values of theirs could move the pixel's display colour by more than N / 255 (the
//               surface's light with both at 1 and both at 0, weighted by what the mirror passes,
//               tone mapped over the colour so far; the light is linear in both with terms of one
//               sign, and the display colour grows with it). Skipped, each takes the middle, 0.5
//               (a shadow ray whose range is empty still gives 1). The bound holds before fog and
//               later bounces, which only shrink the spread as far as tone mapping flattens
//   BOUNDS      1 (default) use the scene's bounding volume, 0 march the whole field
//               everywhere as a plain raymarcher does (the accuracy bench's plain row and its
//               references)
//
// Bounding volume (optional, declared by the scene before this file):
//   #define SCENE_BOUND 1 and `vec4 sceneBound()`: a sphere (centre xyz, radius w) that holds
//     every surface of map() except the ground;
//   #define SCENE_GROUND 1 and `vec4 mapGround(vec3 p)`: the ground plane y = 0 alone
//     (albedo, p.y); map(p) must equal mapGround(p) wherever the bounding sphere is farther
//     away than the ground (a plain union with the objects does that; a smooth one needs its
//     blend radius added to the sphere).
// With both, a primary ray marches only the stretch inside the sphere and meets the ground
// analytically (no creeping along the floor at the horizon), a shadow ray marches only where
// the sphere can still darken its penumbra, and the probes (normals, AO, shadows) sample the
// ground alone where the objects cannot be nearer.
//   #define SCENE_BOX 1 and `vec3 sceneBoxMin()`, `vec3 sceneBoxMax()` (with SCENE_BOUND): an
//     axis-aligned box with the same contract as the sphere (the renderer uses whichever is
//     nearer to the point, and marches where the ray is inside both), and above whose top
//     map(p).w >= p.y - sceneBoxMax().y (blends included). A flat field of shapes fits a box
//     far tighter than a sphere: its primary rays march only inside the box, the floor in front
//     of it is met analytically, and a shadow ray stops where its height above the box keeps
//     the penumbra term at 1 (under a high light: most of its shadow rays).
#ifndef SDF_RENDER_RENDER_GLSL
#define SDF_RENDER_RENDER_GLSL

#ifndef BOUNCE_STEPS
#define BOUNCE_STEPS 0
#endif
#ifndef BOUNCE_LIGHT
#define BOUNCE_LIGHT 0
#endif
#ifndef BOUNCE_BOUND
#define BOUNCE_BOUND 4
#endif
#ifndef SHADOWS
#define SHADOWS 2
#endif
#ifndef AO
#define AO 1
#endif
#ifndef SPECULAR
#define SPECULAR 1
#endif
#ifndef PBR
#define PBR 0
#endif
#ifndef REFLECTIONS
#define REFLECTIONS 0
#endif
#ifndef FOG
#define FOG 1
#endif
#ifndef DEBUG_VIEW
#define DEBUG_VIEW 0
#endif
#ifndef NORMALS
#define NORMALS 0
#endif
#ifndef MARCH_FIXED
#define MARCH_FIXED 0
#endif
#ifndef EPS_MODE
#define EPS_MODE 0
#endif
#ifndef BOUNDS
#define BOUNDS 1
#endif
// Over-relaxed sphere tracing (marchRange): steps of OVERRELAX_OMEGA times the distance where the
// field is a bound (sceneLipschitz() <= 1); plain steps for an estimate, the Mandelbulb's, where it
// moved 4 % of the pixels. NVIDIA H200: 2-4 % off every bounded scene's frame at the same geometry
// error (docs/performance.md, session 13). 0: plain sphere tracing (the CPU reference's).
#ifndef OVERRELAX
#define OVERRELAX 1
#endif
#ifndef OVERRELAX_OMEGA
#define OVERRELAX_OMEGA 1.2f
#endif
#ifndef SCENE_BOUND
#define SCENE_BOUND 0
#endif
// SHADOW_BOX_RANGE (on): a soft shadow ray marches only where it passes near the scene's box as
// well as its sphere (shadowRange). 0: the sphere's penumbra cone and the box's top alone.
#ifndef SHADOW_BOX_RANGE
#define SHADOW_BOX_RANGE 1
#endif
#ifndef SCENE_GROUND
#define SCENE_GROUND 0
#endif
// A scene whose map() repeats work that depends on uniforms only (a character's skeleton: the
// sin/cos of its walk) may define `void sceneSetup()` and `#define SCENE_SETUP 1`: the renderer
// calls it once per invocation (renderFrom, coneStart) before any map(), and map() reads what it
// left in SCENE_STATE globals. The field is the same; only where it is computed moves.
#ifndef SCENE_SETUP
#define SCENE_SETUP 0
#endif
#ifndef SCENE_STATE_FRAME
#define SCENE_STATE_FRAME 0   // set by the blocks src/shader/shader.cpp generates (SCENE_SETUP_FRAME)
#endif
void callSceneSetup() {
#if defined(SCENE_EVALUATOR) && SCENE_EVALUATOR
    evalPrepare();   // the evaluator program (render/eval.glsl): the scene's setup and its argument-less hooks, run once
#elif SCENE_SETUP && !SCENE_STATE_FRAME
    sceneSetup();
#endif
}
#define USE_BOUND (BOUNDS && SCENE_BOUND)
#ifndef SCENE_BOX
#define SCENE_BOX 0
#endif
#define USE_GROUND (BOUNDS && SCENE_BOUND && SCENE_GROUND)
#define USE_BOX (BOUNDS && SCENE_BOUND && SCENE_BOX)

#include "render/uniforms.glsl"

#include "render/work.glsl"

#if USE_BOUND
// Distance from p to the scene's bounding volume (<= 0 inside): the sphere, and the box where
// the scene declares one (both hold the objects, so the farther of the two is still a bound).
float boundDistance(vec3 p) {
    vec4 b = sceneBound();
    float d = length(p - vec3(b.x, b.y, b.z)) - b.w;
#if USE_BOX
    vec3 lo = sceneBoxMin();
    vec3 hi = sceneBoxMax();
    d = max(d, length(max(max(lo - p, p - hi), vec3(0.0f))));
#endif
    return d;
}
#endif

// map(), or the ground alone where it is nearer than the objects' bounding volume (then the
// objects cannot be the nearest surface, so the result is still a distance bound).
vec4 mapNear(vec3 p) {
#if USE_GROUND
    vec4 g = mapGround(p);
    if (g.w < boundDistance(p)) return g;
#endif
    return map(p);
}
#define PROBE_MAP mapNear

// A scene whose map() is its objects smooth-unioned into the floor may say so (SCENE_OBJECTS 1): it
// declares `vec4 mapObjects(vec3 p)` and `float sceneGroundBlend()`, and map(p) equals
// fOpUnionSmoothColor(mapGround(p), mapObjects(p), sceneGroundBlend()).
#ifndef SCENE_OBJECTS
#define SCENE_OBJECTS 0
#endif
// The floor's union as map() computes it from the floor and the objects (render/one_site.glsl reads
// the objects alone and composes map() so).
#ifndef SCENE_MAP_OF
#define SCENE_MAP_OF(g, o) fOpUnionSmoothColor(g, o, sceneGroundBlend())
#endif
// The floor's union's distance as map() computes it (a scene with the blend's reciprocal at hand
// defines its own: lib/field_scene.glsl).
#ifndef SCENE_GROUND_SMIN
#define SCENE_GROUND_SMIN(g, o) sminPoly(g, o, sceneGroundBlend())
#endif
// SHADOW_OBJECT_STEP (on where a scene declares its objects): the soft shadows' safe step past the
// floor (shadowStep's hSafe). A shadow ray from above the ground with k s rd.y >= 1 (k its hardness,
// s the step scale) is at least t rd.y above the floor at t, so where the floor alone makes the
// field (the objects a blend radius kf or more above it) the penumbra term is >= 1. Elsewhere
// the blend lowers the field by at most kf / 4 below min(floor, objects), and the floor is within
// kf of the objects there: the field is >= objects - 1.25 kf, which is 1-Lipschitz. So the ray
// may step by that where it is larger than the field: from the floor between the fields' shapes
// it no longer creeps up a step the size of its height at a time. Every sample still reads the
// field; only where the samples fall moves. 0: the field's own step.
#ifndef SHADOW_OBJECT_STEP
#define SHADOW_OBJECT_STEP 1
#endif
#if USE_GROUND && SCENE_OBJECTS
// At p, where the floor's height is g: (the field, as map() computes it; objects - 1.25 kf, below
// every surface but the plane y = 0). The shadow rays' and the primary march's object steps.
vec2 fieldAndObjectBound(vec3 p, float g) {
    float o = mapObjects(p).w;
    return vec2(SCENE_GROUND_SMIN(g, o), o - 1.25f * max(sceneGroundBlend(), 0.0f));
}
#endif
vec2 shadowProbe(vec3 ro, vec3 rd, float t, float k) {
    vec3 p = ro + rd * t;
#if USE_GROUND && SCENE_OBJECTS && SHADOW_OBJECT_STEP
    float g = mapGround(p).w;
    if (g < boundDistance(p)) return vec2(g);   // as mapNear: the floor alone
    vec2 fo = fieldAndObjectBound(p, g);
    if (ro.y >= 0.0f && k * rd.y >= max(1.0f, sceneLipschitz())) return vec2(fo.x, max(fo.x, fo.y));
    return vec2(fo.x);
#else
    return vec2(mapNear(p).w);
#endif
}
#define SHADOW_PROBE(ro, rd, t, k) shadowProbe(ro, rd, t, k)
#include "lib/shading.glsl"

#include "render/intervals.glsl"

// Result of marching one ray.
struct Hit {
    float t;       // distance along the ray (u_maxDist on a miss)
    float steps;   // map evaluations used
    bool hit;
    vec3 albedo;   // from map() at the hit
    float d;       // map().w there: the field's value at the hit (forward normals start from it)
};

// Unit ray direction through a pixel for the look-at camera (vertical fov u_fov).
// CAMERA_UNIFORMS (on for the GPU): the basis from uniforms.glsl's u_camForward, u_camDX, u_camDY,
// not computed in every pixel.
#if !defined(CAMERA_UNIFORMS) && (defined(SDFVJ_COMPUTE) || defined(SDFVJ_FRAGMENT))
#define CAMERA_UNIFORMS 1
#endif
#ifndef CAMERA_UNIFORMS
#define CAMERA_UNIFORMS 0
#endif
vec3 cameraRay(vec2 fragCoord) {
#if CAMERA_UNIFORMS
    vec2 c = fragCoord - 0.5f * u_resolution;
    return normalize(u_camForward + c.x * u_camDX + c.y * u_camDY);
#else
    vec3 forward = safeNormalize(u_camTarget - u_camPos);
    vec3 up = abs(forward.y) > 0.999f ? vec3(0.0f, 0.0f, 1.0f) : vec3(0.0f, 1.0f, 0.0f);
    // x is screen-right when looking down +Z (the Unity-style convention of the seeds and
    // the scene headers: a camera at z = -6 looking at the origin sees +X on the right)
    vec3 right = normalize(cross(up, forward));
    vec3 camUp = cross(forward, right);
    vec2 uv = (fragCoord - 0.5f * u_resolution) / max(u_resolution.y, 1.0f);
    float tanHalf = tan(radians(clamp(u_fov, 1.0f, 179.0f)) * 0.5f);
    return normalize(forward + (uv.x * right + uv.y * camUp) * (2.0f * tanHalf));
#endif
}

// Angle subtended by one pixel (vertically) at the camera.
float pixelAngle() {
#if CAMERA_UNIFORMS
    return u_pixelAngle;
#else
    return 2.0f * tan(radians(clamp(u_fov, 1.0f, 179.0f)) * 0.5f) / max(u_resolution.y, 1.0f);
#endif
}

// Hit threshold grows with distance so far surfaces need no more precision than a pixel.
float hitEpsilon(float t) {
#if EPS_MODE == 1
    return u_hitEps;
#elif EPS_MODE == 2
    return u_hitEps * t * pixelAngle();
#else
    return u_hitEps * max(1.0f, t);
#endif
}

#include "render/march.glsl"

// The shadow ray's stretch worth marching: all of [tmin, tmax], or with the scene's bound the
// part of it where the objects can darken the penumbra (k is the hardness; hard shadows pass
// a huge k, which leaves just the sphere). Returns (from, to), empty if from > to.
vec2 shadowRange(vec3 ro, vec3 rd, float tmin, float tmax, float k) {
#if USE_BOX
    float ks = k * sceneStepScale();
    // Above the box a sample's penumbra term is at least k * s * (height above it) / t, which
    // stays >= 1 from t = k s (top - ro.y) / (k s rd.y - 1) on (s: the step scale the shadow
    // applies to map()); the ray's stretch past that changes nothing.
    if (ks * rd.y > 1.0f) tmax = min(tmax, ks * (sceneBoxMax().y - ro.y) / (ks * rd.y - 1.0f));
#endif
#if USE_BOUND
#if SCENE_GROUND
    // An upward ray from above the ground keeps k * height / t >= k * rd.y from the ground.
    if (ro.y < 0.0f || k * rd.y < 1.0f) return vec2(tmin, tmax);
#endif
    vec2 r = penumbraInterval(ro, rd, sceneBound(), k);
    r = vec2(max(r.x, tmin), min(r.y, tmax));
#if USE_BOX && SHADOW_BOX_RANGE
    // Beside the box too: up to the stretch's end T, a sample farther than T / (k s) from the box
    // is farther than t / (k s) from every object, so its penumbra term is >= 1; the ray can darken
    // nothing past where it leaves the box widened by that, nor at all if it never enters it. (Its
    // start stays the sphere's: a later one would move every sample, and the penumbra with them.)
    float e = r.y / max(ks, 1e-6f);
    vec2 near = boxInterval(ro, rd, sceneBoxMin() - vec3(e), sceneBoxMax() + vec3(e));
    r.y = near.x <= near.y ? min(r.y, near.y) : -1e30f;
#endif
    return r;
#else
    return vec2(tmin, tmax);
#endif
}

// Forward and tetrahedron sample at a tenth of central's offset: the same error (docs/accuracy.md).
// d: the field's value at p, which the march read with the albedo; forward differences start from
// it, so they take 3 map() calls (tetrahedron 4, central 6).
vec3 surfaceNormal(vec3 p, float t, float d) {
    float eps = u_normalEps * max(1.0f, t);
#if NORMALS == 1
    return calcNormalForwardFrom(p, 0.1f * eps, d);
#elif NORMALS == 2
    return calcNormalTetra(p, 0.1f * eps);
#else
    return calcNormalCentral(p, eps);
#endif
}

// The same where the field's value at p is not at hand (one map() call more for forward).
vec3 surfaceNormal(vec3 p, float t) {
#if NORMALS == 1
    return surfaceNormal(p, t, PROBE_MAP(p).w);
#else
    return surfaceNormal(p, t, 0.0f);
#endif
}

#include "render/quad_reflections.glsl"
#include "render/shade.glsl"

// The step budget of a ray: a reflection's is BOUNCE_STEPS where it sets one.
int rayMaxSteps(int bounce) { return bounce == 0 || BOUNCE_STEPS <= 0 ? u_maxSteps : min(u_maxSteps, BOUNCE_STEPS); }

// The primary ray (from `ro` along `rd`) and each mirror bounce run one loop body: one copy of the
// march, the normal and the shading, not one per bounce (NVIDIA ran a bounce's own copy at 5x the
// cost per map() call, and it doubled what the driver compiles); the trip count reads a uniform, so
// it is not unrolled. The primary ray is marched from tStart (the compute path's cone pre-pass; 0
// from the eye), or its hit is `given` (supersample.glsl marches a pixel's samples first).
// Returns linear radiance (or a DEBUG_VIEW's value).
vec4 traceRay(vec3 ro, vec3 rd, float tStart, Hit first, bool given) {
    vec3 col = vec3(0.0f);
    vec3 throughput = vec3(1.0f);
    int bounces = (u_effectsOff & EFFECT_OFF_REFLECTIONS) != 0 ? 0 : REFLECTIONS;
    float tNext = 0.0f;   // where a reflected ray starts (march.glsl mirrorStart)
    int firstBounce = 0;
#if USE_QUAD_DEFER
    if (g_deferPass) {   // a listed pixel: its bounce, from where the frame left it
        ro = g_deferRo, rd = g_deferRd, tNext = g_deferTNext, throughput = g_deferThroughput, col = g_deferCol;
        firstBounce = 1;
    }
#endif
    for (int bounce = firstBounce; bounce <= bounces; bounce++) {
        WORK_PHASE(bounce == 0 ? 0 : 4);
#if USE_QUAD_REFLECTIONS
        if (bounce == 1 && !g_quadPass && !g_deferPass) {   // the quad's bounce, traced before the frame
#if !USE_QUAD_SHADE
            quadFind(ro);   // (found here, after the shading: nothing of it stays live through the shadow and AO)
#endif
            vec3 seen = quadBounceSeen();
            if (seen.x >= 0.0f) {
                col += throughput * seen;
                break;
            }
#if USE_QUAD_DEFER
            if (quadDeferPush(g_pixel, ro, rd, tNext, throughput, col)) {
                g_deferred = true;
                break;
            }
#endif
        }
#endif
        Hit h = bounce == 0 && given ? first : march(ro, rd, bounce == 0 ? tStart : tNext, rayMaxSteps(bounce));
        vec3 n = vec3(0.0f, 1.0f, 0.0f);
        WORK_PHASE(bounce == 0 ? 1 : 5);
        if (h.hit) n = surfaceNormal(ro + rd * h.t, h.t, h.d);
#if DEBUG_VIEW == 1
        return vec4(heatmap(h.steps / max(float(u_maxSteps), 1.0f)), 1.0f);
#elif DEBUG_VIEW == 2
        float depth = h.hit ? 1.0f - h.t / max(u_maxDist, 1e-3f) : 0.0f;
        return vec4(vec3(depth), 1.0f);
#elif DEBUG_VIEW == 3
        return vec4(h.hit ? n * 0.5f + 0.5f : vec3(0.0f), 1.0f);
#elif DEBUG_VIEW == 4
        float outOfSteps = 0.0f;
#if MARCH_FIXED
        if (!h.hit && h.steps >= float(u_maxSteps) && max(u_fixedStep, 1e-4f) * float(u_maxSteps) < u_maxDist) outOfSteps = 0.5f;
#else
        if (h.hit && h.steps >= float(u_maxSteps) && map(ro + rd * h.t).w >= hitEpsilon(h.t)) outOfSteps = 0.5f;
#endif
        vec2 oct = octEncode(n);
        return vec4(h.hit ? h.t : -1.0f, oct.x, oct.y, h.steps + outOfSteps);
#endif
#if USE_QUAD_REFLECTIONS
        if (bounce == 0 && h.hit) {
            g_firstT = h.t, g_firstN = n;
#if USE_QUAD_SHADE
            if (!g_quadPass) quadFind(ro + rd * h.t);   // the quad lending this pixel its light and its bounce
#endif
        }
        if (g_quadPass) {   // the centre's bounce; its own light too where it lends it (shadeSurface keeps it)
            if (bounce == 1 || USE_QUAD_SHADE != 0) {
                vec3 seen = shadeRay(ro, rd, h, n, bounce, col, throughput);
                if (bounce == 1) g_bounceLight = seen;
            }
        } else
#endif
        col += throughput * shadeRay(ro, rd, h, n, bounce, col, throughput);
        if (!h.hit || bounce == bounces) break;
        throughput *= fresnelSchlick(max(dot(n, -rd), 0.0f), baseReflectance(h.albedo, u_metalness)) * (1.0f - u_roughness);
        tNext = bounce == 0 ? mirrorStart(ro, rd, h, n, tStart) : 0.0f;
        ro = ro + rd * h.t + n * (4.0f * hitEpsilon(h.t));
        rd = reflect(rd, n);
    }
#if WORK_VIEW   // (8: log: 1, 3, 7, 15, 31, 63, 127 calls in even steps)
    return DEBUG_VIEW == 8 ? vec4(heatmap(log2(1.0f + workView().x) / 7.0f), 1.0f) : workView();
#endif
    return vec4(col, 1.0f);
}

#include "render/one_site.glsl"

// tStart: where the primary ray starts (the compute path's cone pre-pass; 0 marches from the eye).
vec4 renderFrom(vec2 fragCoord, float tStart) {
    callSceneSetup();
    WORK_RESET();
    Hit none = Hit(0.0f, 0.0f, false, vec3(0.0f), 0.0f);
#if USE_ONE_SITE
    vec4 c = traceRayOneSite(u_camPos, cameraRay(fragCoord), tStart);
#else
    vec4 c = traceRay(u_camPos, cameraRay(fragCoord), tStart, none, false);
#endif
#if DEBUG_VIEW
    return c;
#else
    return pixelColor(displayColor(vec3(c.x, c.y, c.z)), fragCoord);
#endif
}

vec4 render(vec2 fragCoord) { return renderFrom(fragCoord, 0.0f); }

#endif
