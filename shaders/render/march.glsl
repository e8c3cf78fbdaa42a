// march.glsl - the primary ray's marcher (GLSL/C++ subset), included by render.glsl after its
// Hit, cameraRay and hitEpsilon: marchRange (sphere tracing, over-relaxed with OVERRELAX, or a
// fixed step), march (only the stretch inside the scene's bound, the ground met analytically) and
// the compute path's cone pre-pass (coneStart).
#ifndef SDF_RENDER_MARCH_GLSL
#define SDF_RENDER_MARCH_GLSL

// A distance *estimate* (sceneLipschitz() > 1: the Mandelbulb's), not a bound: no step may lean on
// it being one (the over-relaxed step, the cone pre-pass).
bool sceneIsEstimate() { return sceneLipschitz() > 1.0f; }

// ALBEDO_AT_HIT (on): the sphere-tracing loop reads the distance alone, so the compiler drops the
// albedo's work from every step, and the albedo is read once where the march stopped. NVIDIA H200,
// one interleaved run against copies with it 0: 1080p 1.8-7.1 % off every scene (midi 0.198 ->
// 0.184 ms, field150 0.687 -> 0.646), 4K 0.9-5.2 %; the same accuracy rows; midi's compile 654 ->
// 740 ms, character's 2189 -> 2221 ms (one more map() call site: docs/performance.md, session 16).
#ifndef ALBEDO_AT_HIT
#define ALBEDO_AT_HIT 1
#endif

// MARCH_OBJECT_STEP (on where the scene declares SCENE_OBJECTS): the primary ray steps past the floor
// by the objects' distance. Every surface point is on the plane y = 0 (where the objects are the
// floor's blend kf or more above it, the field is the floor's height) or has objects <= 1.25 kf
// (elsewhere the field is >= objects - 1.25 kf, shadowProbe in render.glsl). From a point whose
// objects read o, no surface of the second kind lies within o - 1.25 kf, and the ray meets the
// plane only at tGround: a step of min(o - 1.25 kf, tGround - t) crosses no surface, in any
// direction for the first and along the ray for the second (all the over-relaxed gap test needs).
// The ray steps by that where it is larger than the field: over the floor between the fields'
// shapes it no longer creeps down a step the size of its height at a time. The hit test still
// reads the field. 0: the field's own step.
#ifndef MARCH_OBJECT_STEP
#define MARCH_OBJECT_STEP 1
#endif
#define USE_MARCH_OBJECT_STEP (USE_GROUND && SCENE_OBJECTS && MARCH_OBJECT_STEP && !MARCH_FIXED)
#if USE_MARCH_OBJECT_STEP
// (the field at p, a step the ray may take from it), groundLeft: how far along the ray the plane is.
vec2 marchProbe(vec3 p, float groundLeft) {
    vec2 fo = fieldAndObjectBound(p, mapGround(p).w);
    return vec2(fo.x, max(fo.x, min(fo.y, groundLeft)));
}
#endif

// Marches the whole field from tmin in at most maxSteps steps; past tmax the ray has missed.
Hit marchRange(vec3 ro, vec3 rd, float tmin, float tmax, int maxSteps) {
    float t = tmin;
    float steps = 0.0f;
#if MARCH_FIXED
    float prevT = t;
    for (int i = 0; i < maxSteps; i++) {
        steps += 1.0f;
        float d = map(ro + rd * t).w;
        if (d < hitEpsilon(t)) {
            // crossed the surface: bisect between the last two samples
            float a = prevT;
            float b = t;
            for (int j = 0; j < 8; j++) {
                float m = 0.5f * (a + b);
                if (map(ro + rd * m).w < hitEpsilon(m)) b = m; else a = m;
            }
            vec4 m = map(ro + rd * b);
            return Hit(b, steps, true, vec3(m.x, m.y, m.z), m.w);
        }
        prevT = t;
        t += max(u_fixedStep, 1e-4f);
        if (t > tmax) break;
    }
#elif ALBEDO_AT_HIT
    float stepScale = u_stepFactor / max(1.0f, sceneLipschitz());
    bool stopped = false;
#if OVERRELAX
    float omega = sceneIsEstimate() ? 1.0f : OVERRELAX_OMEGA, prevR = 0.0f, stepLen = 0.0f;
#endif
#if USE_MARCH_OBJECT_STEP
    // where the ray meets the plane y = 0: never going up; from under it, no shortcut (0)
    float tGround = ro.y < 0.0f ? 0.0f : rd.y < 0.0f ? -ro.y / rd.y : 1e30f;
#endif
    for (int i = 0; i < maxSteps; i++) {
        steps += 1.0f;
#if USE_MARCH_OBJECT_STEP
        float groundLeft = max(tGround - t, 0.0f);
        vec2 probe = marchProbe(ro + rd * t, groundLeft);
        float d = probe.x, ds = probe.y;
#else
        float d = map(ro + rd * t).w, ds = d;
#endif
#if OVERRELAX
        float r = ds * stepScale;
        bool gap = omega > 1.0f && abs(r) + prevR < stepLen;
        if (gap) {
            stepLen -= omega * stepLen;
            omega = 1.0f;
        } else {
            if (d < hitEpsilon(t)) { stopped = true; break; }
            stepLen = r * omega;
#if USE_MARCH_OBJECT_STEP
            stepLen = min(stepLen, max(r, groundLeft));   // not over-relaxed past the plane
#endif
            prevR = abs(r);
        }
        t += stepLen;
#else
        if (d < hitEpsilon(t)) { stopped = true; break; }
        t += ds * stepScale;
#endif
        if (t > tmax) return Hit(u_maxDist, steps, false, vec3(0.0f), 0.0f);
    }
    // A hit, or out of steps short of the far plane (creeping along a surface: called a hit, as below).
    if (stopped || steps > 0.0f) {
        vec4 m = map(ro + rd * t);
        return Hit(t, steps, true, vec3(m.x, m.y, m.z), m.w);
    }
#else
    float stepScale = u_stepFactor / max(1.0f, sceneLipschitz());
    vec4 m = vec4(0.0f);
#if OVERRELAX
    // Over-relaxed sphere tracing (Keinert et al. 2014): steps of OVERRELAX_OMEGA times the
    // distance; where the new point's sphere and the last one's leave a gap, step back to plain
    // sphere tracing (the point is not tested for a hit, so no surface is skipped). A distance
    // estimate steps plainly from the start.
    float omega = sceneIsEstimate() ? 1.0f : OVERRELAX_OMEGA, prevR = 0.0f, stepLen = 0.0f;
    for (int i = 0; i < maxSteps; i++) {
        steps += 1.0f;
        m = map(ro + rd * t);
        float r = m.w * stepScale;
        bool gap = omega > 1.0f && abs(r) + prevR < stepLen;
        if (gap) {
            stepLen -= omega * stepLen;   // back to the last point plus a plain step
            omega = 1.0f;
        } else {
            if (m.w < hitEpsilon(t)) return Hit(t, steps, true, vec3(m.x, m.y, m.z), m.w);
            stepLen = r * omega;
            prevR = abs(r);
        }
        t += stepLen;
        if (t > tmax) return Hit(u_maxDist, steps, false, vec3(0.0f), 0.0f);
    }
#else
    for (int i = 0; i < maxSteps; i++) {
        steps += 1.0f;
        m = map(ro + rd * t);
        if (m.w < hitEpsilon(t)) return Hit(t, steps, true, vec3(m.x, m.y, m.z), m.w);
        t += m.w * stepScale;
        if (t > tmax) return Hit(u_maxDist, steps, false, vec3(0.0f), 0.0f);
    }
#endif
    // Out of steps short of the far plane: the ray is creeping along a surface (grazing
    // silhouettes, a floor at the horizon, a heavily twisted field). Calling it a hit
    // avoids sky-coloured holes; DEBUG_VIEW 1 shows where it happens.
    if (steps > 0.0f) {
        m = map(ro + rd * t);   // (m was read one step back)
        return Hit(t, steps, true, vec3(m.x, m.y, m.z), m.w);
    }
#endif
    return Hit(u_maxDist, steps, false, vec3(0.0f), 0.0f);
}

// (The C++ reference's whole-field march, scene_instance.inc marchWhole.)
Hit marchRange(vec3 ro, vec3 rd, float tmin, float tmax) { return marchRange(ro, rd, tmin, tmax, u_maxSteps); }

// GROUND_SNAP 0: floor hits stay where the march stopped (the renderer before session 15; a scene
// copy can define it to measure the difference).
#ifndef GROUND_SNAP
#define GROUND_SNAP 1
#endif
#if USE_GROUND && GROUND_SNAP
// A hit on the bare floor lands on the plane itself. The march stops anywhere up to eps short of
// a surface; on the floor that moved the edges of its albedo (a checker, grid lines) by a fraction
// of a pixel wherever a march started elsewhere (the compute path's cone pre-pass) or stepped
// otherwise, and those pixels flipped colour. Where map() returned the ground (its albedo, and a
// point within eps of y = 0) the hit is the plane's, analytic, with the albedo read there. A
// surface blended into the floor (a smooth union) returns an albedo of its own: left as marched.
Hit onGround(vec3 ro, vec3 rd, Hit h) {
    if (!h.hit || rd.y >= 0.0f || ro.y < 0.0f) return h;
    vec3 p = ro + rd * h.t;
    if (p.y > hitEpsilon(h.t)) return h;
    vec4 g = mapGround(p);
    // (to 1e-4, not exactly: the two map() call sites may round differently, FMA contraction)
    if (max(abs(g.x - h.albedo.x), max(abs(g.y - h.albedo.y), abs(g.z - h.albedo.z))) > 1e-4f) return h;
    float tg = -ro.y / rd.y;
    vec4 at = mapGround(ro + rd * tg);
    return Hit(tg, h.steps, true, vec3(at.x, at.y, at.z), at.w);
}
#endif

// The primary (and reflection) ray: with the scene's bound only the stretch inside the sphere
// is marched, and the ground is met analytically. One marchRange call site: one inlined loop.
// maxSteps: the march's step budget (traceRay gives a reflection BOUNCE_STEPS).
#if USE_BOUND
// The stretch of the ray worth marching from tmin: (from, to, where it meets the ground: past
// 2 u_maxDist where it does not). march() and the one-site renderer's march (render/one_site.glsl).
vec3 marchStretch(vec3 ro, vec3 rd, float tmin) {
    float tGround = 2.0f * u_maxDist + 1.0f;   // no ground in front
    float a = tmin, b = u_maxDist;   // under the floor no shortcut: the whole field from tmin
    if (SCENE_GROUND == 0 || ro.y >= 0.0f) {
#if SCENE_GROUND
        if (rd.y < 0.0f) tGround = -ro.y / rd.y;   // (before tmin only where the cone went past the floor)
#endif
        vec2 inside = sphereInterval(ro, rd, sceneBound());
        a = max(inside.x, tmin);
        b = min(min(inside.y, tGround), u_maxDist);
#if USE_BOX
        vec2 box = boxInterval(ro, rd, sceneBoxMin(), sceneBoxMax());
        a = max(a, box.x);
        b = min(b, box.y);
#endif
    }
    return vec3(a, b, tGround);
}
#endif

Hit march(vec3 ro, vec3 rd, float tmin, int maxSteps) {
#if USE_BOUND
    vec3 stretch = marchStretch(ro, rd, tmin);
    float a = stretch.x, b = stretch.y, tGround = stretch.z;
    float steps = 0.0f;
    if (a <= b) {
        Hit h = marchRange(ro, rd, a, b, maxSteps);
#if USE_GROUND && GROUND_SNAP
        if (h.hit) return onGround(ro, rd, h);
#else
        if (h.hit) return h;
#endif
        steps = h.steps;
    }
#if SCENE_GROUND
    if (tGround <= u_maxDist) {   // the march found nothing before the floor, so the floor alone is there
        vec4 g = mapGround(ro + rd * tGround);
        return Hit(tGround, steps + 1.0f, true, vec3(g.x, g.y, g.z), g.w);
    }
#endif
    return Hit(u_maxDist, steps, false, vec3(0.0f), 0.0f);
#else
    return marchRange(ro, rd, tmin, u_maxDist, maxSteps);
#endif
}
Hit march(vec3 ro, vec3 rd, float tmin) { return march(ro, rd, tmin, u_maxSteps); }

// The low-resolution pre-pass of the compute path (main_comp.glsl): how far every pixel ray of a
// tile (pixel centres lo..hi) can start. One ray through the tile's centre marches with spheres
// that hold the tile's whole bundle of rays: a pixel ray leaves the centre ray by at most
// t * alpha (alpha: the widest chord between the centre direction and a corner's), so for t' in
// [t, t + s] with s = (d - e - t alpha) / (1 + alpha) it stays within d - e of the centre ray's
// point at t, whose nearest surface is d away: every pixel ray is at least e = hitEpsilon(t + d)
// from any surface up to the returned distance, so no pixel march could have stopped before it.
// d is a lower bound of the distance: map() over the scene's Lipschitz bound (and the step
// factor where it under-relaxes), or outside the bounding volume the distance to it and to the
// ground. Used as the primary ray's tmin; 0 where the pre-pass is off or the field is an estimate.
float coneDistance(vec3 p, float t, float alpha, float inv) {
#if USE_BOUND
    float d = boundDistance(p);
#if SCENE_GROUND
    d = min(d, mapGround(p).w);
#endif
    // The cheap bound only while it still lets the cone step on; then the field itself.
    if (d - hitEpsilon(t + max(d, 0.0f)) - t * alpha < hitEpsilon(t)) d = max(d, mapNear(p).w * inv);
    return d;
#else
    return map(p).w * inv;
#endif
}

// CONE_PAST_FLOOR (on where a scene declares its objects over a floor, SCENE_OBJECTS): the cone does
// not stop at the floor's plane y = 0, which the primary march meets analytically: its distance is
// the objects' bound alone (the bounding volume, then the larger of the field and the objects'
// field less 1.25 kf, as MARCH_OBJECT_STEP reads them: below every surface but the plane). A pixel
// ray whose tile's cone went past its floor point skips its march (march(): nothing to march before
// the floor) where it used to creep down to the floor from the cone's stop.
// CONE_MIRROR (with it, in a frame that draws reflections): the cone follows the unfolded ray. A
// pixel ray that meets the floor goes on as its mirror image, which is the ray reflected there, so
// the cone also keeps clear of the objects' mirror images (the same bounds at the point's mirror
// image, less 6 hit thresholds: the reflected ray leaves from 4 thresholds above a hit that lies
// within one of the plane), and a ray reflected off the plane (normal straight up) starts at the
// cone's distance less the primary ray's length (mirrorStart). On the floor between the fields'
// shapes the reflected march took 2.5x the primary one's calls (`bench work`, session 28).
// NVIDIA H200, one interleaved run (docs/performance.md, session 29): CONE_PAST_FLOOR took 1.7-4.0 %
// off full lighting at 1080p and 4K (field150 4K 1.419 -> 1.372 ms, character 0.478 -> 0.464);
// CONE_MIRROR saves the reflected march 6-12 % of its calls but cost the show 1.5-1.9 % (field150
// 7680x4320 12.18 -> 12.38 ms): its cone reads the field twice a step and runs further. Off.
#ifndef CONE_PAST_FLOOR
#define CONE_PAST_FLOOR 1
#endif
#ifndef CONE_MIRROR
#define CONE_MIRROR 0
#endif
#if USE_GROUND && SCENE_OBJECTS
float coneDistanceUnfolded(vec3 p, float t, float alpha, float inv, bool mirror) {
    vec3 q = vec3(p.x, -p.y, p.z);
    float real = boundDistance(p), image = mirror ? boundDistance(q) : 1e30f;
    float d = min(real, image - 6.0f * hitEpsilon(t + max(image, 0.0f)));
    if (d - hitEpsilon(t + max(d, 0.0f)) - t * alpha < hitEpsilon(t)) {
        vec2 fo = fieldAndObjectBound(p, mapGround(p).w);   // the field, and the objects less 1.25 kf
        real = max(real, max(fo.x, fo.y) * inv);
        if (mirror) image = max(image, fieldAndObjectBound(q, 0.0f).y * inv);
        d = min(real, image - 6.0f * hitEpsilon(t + max(image, 0.0f)));
    }
    return d;
}
#if CONE_PAST_FLOOR && CONE_MIRROR && REFLECTIONS > 0
#define CONE_MODE 2
#elif CONE_PAST_FLOOR
#define CONE_MODE 1
#else
#define CONE_MODE 0
#endif
#define HAS_CONE_UNFOLDED 1
#else
#define CONE_MODE 0
#define HAS_CONE_UNFOLDED 0
#endif
#define USE_CONE_MIRROR (CONE_MODE == 2)

// Where a ray reflected off the primary hit h may start (traceRay), given its tile's cone distance:
// past the unfolded cone where h is the floor's plane (within a threshold of it, the normal straight
// up, so the reflected ray is the unfolded one's mirror image) and the reflected ray climbs at least
// as fast as its hit threshold grows (it cannot stop on the plane it leaves). 0 elsewhere.
float mirrorStart(vec3 ro, vec3 rd, Hit h, vec3 n, float tCone) {
#if USE_CONE_MIRROR
    vec3 p = ro + rd * h.t;
    bool plane = h.hit && n.x == 0.0f && n.y == 1.0f && n.z == 0.0f && abs(p.y) <= hitEpsilon(h.t) && ro.y >= 0.0f;
    if (plane && -rd.y >= hitEpsilon(1.0f)) return max(tCone - h.t, 0.0f);
#endif
    return 0.0f;
}

// CONE_MAX_STEPS: the cone's own step budget (u_maxSteps where it is larger). Any step the cone
// stops at is a safe start, so a lower budget only leaves the last steps to the pixel rays, while
// the pre-pass, a dispatch of few invocations, lasts as long as its slowest cone (the tiles that
// graze a silhouette creep). NVIDIA H200, against no budget (u_maxSteps, 128), one interleaved run:
// 32 took 3-13 % off every bounded scene at 1080p (midi 0.185 -> 0.161 ms, field50 0.506 -> 0.469)
// and 1-4 % at 4K; 24 and 12 gained more at 1080p but lost the fields 3-15 % at 4K; 40 less
// everywhere (docs/performance.md, session 22).
#ifndef CONE_MAX_STEPS
#define CONE_MAX_STEPS 32
#endif
// mode: CONE_MODE (0 stops at the floor, 1 past it, 2 past it clear of the mirror images; the C++
// reference's tests ask for each).
float coneStartFor(vec2 lo, vec2 hi, int mode) {
    callSceneSetup();
    // A distance *estimate* (sceneLipschitz() > 1: the Mandelbulb's) is no bound to build on: a
    // later start changes which filament a ray stops on (3.5 % of its pixels moved by > 8/255,
    // same geometry error), so those scenes march from the eye.
    if (sceneIsEstimate()) return 0.0f;
    vec3 ro = u_camPos;
    vec3 rc = cameraRay(0.5f * (lo + hi));
    float alpha = length(cameraRay(lo) - rc);
    alpha = max(alpha, length(cameraRay(hi) - rc));
    alpha = max(alpha, length(cameraRay(vec2(lo.x, hi.y)) - rc));
    alpha = max(alpha, length(cameraRay(vec2(hi.x, lo.y)) - rc));
    alpha = alpha * 1.001f + 1e-6f;   // the corners' rounding
    float inv = min(u_stepFactor, 1.0f) / max(1.0f, sceneLipschitz());
#if USE_GROUND
    if (ro.y < 0.0f) return 0.0f;   // under the floor the primary march takes no shortcut either
#endif
    float t = 0.0f;
    for (int i = 0; i < min(u_maxSteps, CONE_MAX_STEPS); i++) {
#if HAS_CONE_UNFOLDED
        float d = mode == 0 ? coneDistance(ro + rc * t, t, alpha, inv) : coneDistanceUnfolded(ro + rc * t, t, alpha, inv, mode == 2);
#else
        float d = coneDistance(ro + rc * t, t, alpha, inv);
#endif
        float s = (d - hitEpsilon(t + max(d, 0.0f)) - t * alpha) / (1.0f + alpha);
        if (s < hitEpsilon(t)) break;   // the bundle is near a surface: the pixel rays go on alone
        t += s;
        if (t >= u_maxDist) return u_maxDist;
    }
    return t;
}
float coneStart(vec2 lo, vec2 hi) { return coneStartFor(lo, hi, CONE_MODE); }

#endif
