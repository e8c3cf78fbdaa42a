// one_site.glsl - the pixel's whole trace with ONE call site of the scene's field (GLSL only;
// included by render.glsl after traceRay): the quick first tier of a save (QuickTierText). Each
// call site of map() in a program (the march, the albedo at the hit, the normal, the shadow ray,
// AO) is a copy of the scene's code for the compiler: on llvmpipe, which inlines everything, the
// copies are 63-76 % of a program's build; on NVIDIA the scene's field is most of the quick tier's
// link, and the renderer around it links in 72-108 ms (`sdfvj bench compile`, docs/performance.md
// "Session 40"). Here the march, the normal's samples, the shadow ray, the AO probes and the
// reflection's own are phases of one loop, each iteration reading the field once, at one place:
// the compiler sees the scene's code once. Built with NVIDIA's `unroll none`, a save's first image
// came 18-25 % sooner on an H100 than with the `inline none` tier before it, and drew 5x as fast.
//
// Every phase does what traceRay's functions do, in the same order with the same arithmetic
// (march/marchRange with ALBEDO_AT_HIT, onGround, surfaceNormal, shadowRange and the shadow loops
// of lib/shading.glsl through shadowProbe, ambientOcclusion, shadeSurface, the mirror bounce), so
// it draws the picture traceRay draws (test: `render: the one-site renderer draws the picture the
// renderer's own functions draw`: byte for byte on llvmpipe). Its frames are slower (1.5-1.7x on
// the H100, 1.4-2x on llvmpipe: each iteration pays every phase's branches); it is on screen only
// until the optimized program replaces it. Scenes of objects over a floor (SCENE_OBJECTS) read
// mapObjects() at the site and compose map() from it and the floor (SCENE_MAP_OF), as their map()
// does.
//
// ONE_SITE 1 asks for it; it is used where it covers the variant: no debug view, no
// supersampling, no fixed-step march, the albedo read at the hit. Elsewhere ONE_SITE changes nothing.
#ifndef SDF_RENDER_ONE_SITE_GLSL
#define SDF_RENDER_ONE_SITE_GLSL

#ifndef ONE_SITE
#define ONE_SITE 0
#endif
#define USE_ONE_SITE (ONE_SITE && DEBUG_VIEW == 0 && SUPERSAMPLE == 0 && !MARCH_FIXED && ALBEDO_AT_HIT)

#if USE_ONE_SITE
#define OS_OBJECTS (USE_GROUND && SCENE_OBJECTS)

// Phases that read the field (one iteration each), then the hand-overs between them, which read
// none (a ray that ran past its stretch; the colour once the shadow and AO are known).
const int OS_MARCH = 0, OS_ALBEDO = 1, OS_NORMAL = 2, OS_SHADOW = 3, OS_AO = 4, OS_MISSED = 5, OS_SHADE = 6, OS_DONE = 7;
#if SHADOWS == 1
const float OS_RANGE_K = 1e6f;   // shadowRange's hardness for hard shadows (shadeSurface)
const float OS_PROBE_K = 1e4f;   // ... and shadowHard's probe
#endif

// The trace's state, one set per invocation.
float os_t0;   // where the primary ray started (the cone's distance: mirrorStart)
vec3 os_ro, os_rd, os_col, os_throughput, os_n, os_p;
int os_phase, os_bounce, os_bounces, os_i, os_maxSteps;
Hit os_h;
// march / marchRange
float os_tGround, os_b, os_t, os_steps, os_stepScale, os_omega, os_prevR, os_stepLen, os_tG;
// normal, shadow, AO
vec3 os_nAcc, os_sRo;
float os_nEps, os_sT, os_sRes, os_sPh, os_sTmax, os_shadow, os_aOcc, os_aW, os_aFar, os_occlusion;
bool os_facesLight;

// The march of the ray os_ro, os_rd from tmin (march(): the stretch inside the bound; marchRange's
// set-up). Where nothing is left to march, the ray has missed its stretch (OS_MISSED).
void osBeginMarch(float tmin) {
    os_phase = OS_MARCH;
    os_i = 0;
    os_steps = 0.0f;
    float a = tmin;
    os_b = u_maxDist;
    os_tGround = 2.0f * u_maxDist + 1.0f;
#if USE_BOUND
    vec3 stretch = marchStretch(os_ro, os_rd, tmin);
    a = stretch.x;
    os_b = stretch.y;
    os_tGround = stretch.z;
    if (a > os_b) {
        os_phase = OS_MISSED;
        return;
    }
#endif
    os_t = a;
    os_stepScale = u_stepFactor / max(1.0f, sceneLipschitz());
#if OVERRELAX
    os_omega = sceneIsEstimate() ? 1.0f : OVERRELAX_OMEGA;
    os_prevR = 0.0f;
    os_stepLen = 0.0f;
#endif
#if USE_MARCH_OBJECT_STEP
    os_tG = os_ro.y < 0.0f ? 0.0f : os_rd.y < 0.0f ? -os_ro.y / os_rd.y : 1e30f;
#endif
    if (os_maxSteps <= 0) os_phase = OS_MISSED;
}

void osBeginNormal();
// The march ran past its stretch: the floor met analytically (march()), or nothing.
void osMissed() {
    os_h = Hit(u_maxDist, os_steps, false, vec3(0.0f), 0.0f);
#if USE_BOUND && SCENE_GROUND
    if (os_tGround <= u_maxDist) {
        vec4 g = mapGround(os_ro + os_rd * os_tGround);
        os_h = Hit(os_tGround, os_steps + 1.0f, true, vec3(g.x, g.y, g.z), g.w);
    }
#endif
    if (os_h.hit) osBeginNormal();
    else os_phase = OS_SHADE;
}

void osBeginShadow();
void osBeginNormal() {
    os_phase = OS_NORMAL;
    os_i = SDF_LOOP_ZERO;
    os_p = os_ro + os_rd * os_h.t;
    os_nAcc = vec3(0.0f);
    float eps = u_normalEps * max(1.0f, os_h.t);
    os_nEps = NORMALS == 0 ? eps : 0.1f * eps;
}

// A normal's sample point (calcNormalCentral, calcNormalForwardFrom, calcNormalTetra), and its weight.
vec3 osNormalAxis(int i) {
#if NORMALS == 1
    return vec3(i == 0 ? 1.0f : 0.0f, i == 1 ? 1.0f : 0.0f, i == 2 ? 1.0f : 0.0f);
#elif NORMALS == 2
    return vec3(float(((i + 3) >> 1) & 1) * 2.0f - 1.0f, float((i >> 1) & 1) * 2.0f - 1.0f, float(i & 1) * 2.0f - 1.0f);
#else
    return vec3(i < 2 ? 1.0f : 0.0f, i == 2 || i == 3 ? 1.0f : 0.0f, i > 3 ? 1.0f : 0.0f);
#endif
}
vec3 osNormalPoint(int i) {
#if NORMALS == 0
    float sg = (i & 1) == 0 ? 1.0f : -1.0f;
    return os_p + osNormalAxis(i) * (sg * os_nEps);
#else
    return os_p + osNormalAxis(i) * os_nEps;
#endif
}
const int OS_NORMAL_SAMPLES = NORMALS == 1 ? 3 : NORMALS == 2 ? 4 : 6;

void osBeginAo();
// shadeSurface's shadow ray, from the normal just found; os_lightWanted: shadeSurface's BOUNCE_BOUND
// test (a reflection's shadow and AO skipped, each 0.5, where they cannot move the pixel).
bool os_lightWanted;
void osBeginShadow() {
    os_shadow = 1.0f;
    os_lightWanted = true;
#if BOUNCE_BOUND > 0 && BOUNCE_LIGHT < 2
    if (os_bounce > 0) {
        vec3 spread = displayColor(os_col + os_throughput * litSurface(os_n, os_rd, os_h.albedo, 1.0f, 1.0f)) -
                      displayColor(os_col + os_throughput * litSurface(os_n, os_rd, os_h.albedo, 0.0f, 0.0f));
        os_lightWanted = max(spread.x, max(spread.y, spread.z)) > float(BOUNCE_BOUND) / 255.0f;
    }
#endif
    os_sRo = os_p + os_n * (2.0f * hitEpsilon(os_h.t));
    os_facesLight = dot(os_n, u_lightDir) > 0.0f && (BOUNCE_LIGHT < 2 || os_bounce == 0);
#if SHADOWS == 1 || SHADOWS == 2 || SHADOWS == 3
#if SHADOWS == 1
    vec2 sr = shadowRange(os_sRo, u_lightDir, 0.01f, u_maxDist, OS_RANGE_K);
#else
    vec2 sr = shadowRange(os_sRo, u_lightDir, 0.01f, u_maxDist, u_shadowK);
#endif
    if (os_facesLight && (u_effectsOff & EFFECT_OFF_SHADOWS) == 0 && sr.x <= sr.y && !os_lightWanted) os_shadow = 0.5f;
    else if (os_facesLight && (u_effectsOff & EFFECT_OFF_SHADOWS) == 0 && sr.x <= sr.y && u_shadowSteps > 0) {
        os_phase = OS_SHADOW;
        os_i = 0;
        os_sT = sr.x;
        os_sTmax = sr.y;
        os_sRes = 1.0f;
        os_sPh = 1e10f;
        return;
    }
#endif
    osBeginAo();
}

void osBeginAo() {
    os_occlusion = 1.0f;
#if AO
    if ((u_effectsOff & EFFECT_OFF_AO) == 0 && (BOUNCE_LIGHT < 1 || os_bounce == 0) && !os_lightWanted) os_occlusion = 0.5f;
    else if ((u_effectsOff & EFFECT_OFF_AO) == 0 && (BOUNCE_LIGHT < 1 || os_bounce == 0) && u_aoSamples > 0) {
        os_phase = OS_AO;
        os_i = 0;
        os_aOcc = 0.0f;
        os_aW = 1.0f;
        os_aFar = 0.0f;
        return;
    }
#endif
    os_phase = OS_SHADE;
}

// The ray's colour (shadeRay, with shadeSurface's light once the shadow and AO are known), then the
// mirror bounce or the end (traceRay).
void osShade() {
    vec3 c;
    if (!os_h.hit) {
        c = background(os_rd);
    } else {
        c = litSurface(os_n, os_rd, os_h.albedo, os_shadow, os_occlusion);
#if FOG
        if ((u_effectsOff & EFFECT_OFF_FOG) == 0) c = applyFog(c, os_h.t, background(os_rd), 0.03f);
#endif
    }
    os_col += os_throughput * c;
    if (!os_h.hit || os_bounce == os_bounces) {
        os_phase = OS_DONE;
        return;
    }
    os_throughput *= fresnelSchlick(max(dot(os_n, -os_rd), 0.0f), baseReflectance(os_h.albedo, u_metalness)) * (1.0f - u_roughness);
    float tNext = os_bounce == 0 ? mirrorStart(os_ro, os_rd, os_h, os_n, os_t0) : 0.0f;
    os_ro = os_ro + os_rd * os_h.t + os_n * (4.0f * hitEpsilon(os_h.t));
    os_rd = reflect(os_rd, os_n);
    os_bounce++;
    os_maxSteps = rayMaxSteps(os_bounce);
    osBeginMarch(tNext);
}

// Which AO probe the i-th read is (ambientOcclusion: the farthest first with AO_FARTHEST_FIRST).
int osAoProbe(int i) { return AO_FARTHEST_FIRST != 0 ? (i == 0 ? u_aoSamples - 1 : i - 1) : i; }

vec4 traceRayOneSite(vec3 ro, vec3 rd, float tStart) {
    os_ro = ro;
    os_rd = rd;
    os_t0 = tStart;
    os_col = vec3(0.0f);
    os_throughput = vec3(1.0f);
    os_shadow = 1.0f;
    os_occlusion = 1.0f;
    os_n = vec3(0.0f, 1.0f, 0.0f);
    os_bounces = (u_effectsOff & EFFECT_OFF_REFLECTIONS) != 0 ? 0 : REFLECTIONS;
    os_bounce = 0;
    os_maxSteps = rayMaxSteps(0);
    osBeginMarch(tStart);
    while (os_phase != OS_DONE) {
        if (os_phase == OS_MISSED) {
            osMissed();
            continue;
        }
        if (os_phase == OS_SHADE) {
            osShade();
            continue;
        }
        // Where the field is read this iteration, and whether the floor alone answers (mapNear,
        // shadowProbe: where the floor is nearer than the objects' bound).
        vec3 q = os_phase == OS_MARCH || os_phase == OS_ALBEDO ? os_ro + os_rd * os_t
               : os_phase == OS_NORMAL ? osNormalPoint(os_i)
               : os_phase == OS_SHADOW ? os_sRo + u_lightDir * os_sT
               : os_p + os_n * (0.01f + 0.15f * float(osAoProbe(os_i)) / max(float(u_aoSamples - 1), 1.0f));
        float ground = 1e30f;   // the floor's height at q (its distance), where a probe reads it
        bool floorAlone = false;
#if USE_GROUND
        if (os_phase != OS_ALBEDO) {
            ground = mapGround(q).w;
            floorAlone = os_phase != OS_MARCH && ground < boundDistance(q);   // the march's probe reads the field always
        }
#endif
        // THE call site.
        vec4 m = vec4(0.0f);   // map(q): albedo, distance
        float o = 0.0f;        // the objects' distance (OS_OBJECTS)
        if (!floorAlone) {
#if OS_OBJECTS
            vec4 objects = mapObjects(q);
            o = objects.w;
            if (os_phase == OS_ALBEDO || os_phase == OS_NORMAL || os_phase == OS_AO
#if !SHADOW_OBJECT_STEP
                || os_phase == OS_SHADOW
#endif
#if !USE_MARCH_OBJECT_STEP
                || os_phase == OS_MARCH
#endif
               )
                m = SCENE_MAP_OF(mapGround(q), objects);
#else
            m = map(q);
#endif
        }
        // The probe as each phase's function reads it.
        float near = floorAlone ? ground : m.w;   // mapNear(q).w

        if (os_phase == OS_MARCH) {
            os_steps += 1.0f;
#if USE_MARCH_OBJECT_STEP
            float groundLeft = max(os_tG - os_t, 0.0f);
            vec2 fo = vec2(SCENE_GROUND_SMIN(ground, o), o - 1.25f * max(sceneGroundBlend(), 0.0f));
            float d = fo.x, ds = max(fo.x, min(fo.y, groundLeft));
#else
            float d = m.w, ds = d;
#endif
            bool stopped = false;
#if OVERRELAX
            float r = ds * os_stepScale;
            bool gap = os_omega > 1.0f && abs(r) + os_prevR < os_stepLen;
            if (gap) {
                os_stepLen -= os_omega * os_stepLen;
                os_omega = 1.0f;
            } else if (d < hitEpsilon(os_t)) {
                stopped = true;
            } else {
                os_stepLen = r * os_omega;
#if USE_MARCH_OBJECT_STEP
                os_stepLen = min(os_stepLen, max(r, groundLeft));
#endif
                os_prevR = abs(r);
            }
            if (!stopped) os_t += os_stepLen;
#else
            if (d < hitEpsilon(os_t)) stopped = true;
            else os_t += ds * os_stepScale;
#endif
            if (stopped) os_phase = OS_ALBEDO;
            else if (os_t > os_b) os_phase = OS_MISSED;
            else if (++os_i >= os_maxSteps) os_phase = OS_ALBEDO;   // out of steps short of the far plane: called a hit (marchRange)
        } else if (os_phase == OS_ALBEDO) {
            os_h = Hit(os_t, os_steps, true, vec3(m.x, m.y, m.z), m.w);
#if USE_BOUND && USE_GROUND && GROUND_SNAP
            os_h = onGround(os_ro, os_rd, os_h);
#endif
            osBeginNormal();
        } else if (os_phase == OS_NORMAL) {
#if NORMALS == 1
            os_nAcc += osNormalAxis(os_i) * (near - os_h.d);
#elif NORMALS == 2
            os_nAcc += osNormalAxis(os_i) * near;
#else
            os_nAcc += osNormalAxis(os_i) * (((os_i & 1) == 0 ? 1.0f : -1.0f) * near);
#endif
            if (++os_i >= OS_NORMAL_SAMPLES) {
                os_n = safeNormalize(os_nAcc);
                osBeginShadow();
            }
        } else if (os_phase == OS_SHADOW) {
#if SHADOWS == 1
            const float k = OS_PROBE_K;
#else
            float k = u_shadowK;
#endif
            // shadowProbe(os_sRo, l, t, k)
            vec2 probe = vec2(near);
#if OS_OBJECTS && SHADOW_OBJECT_STEP
            if (!floorAlone) {
                vec2 fo = vec2(SCENE_GROUND_SMIN(ground, o), o - 1.25f * max(sceneGroundBlend(), 0.0f));
                probe = os_sRo.y >= 0.0f && k * u_lightDir.y >= max(1.0f, sceneLipschitz()) ? vec2(fo.x, max(fo.x, fo.y)) : vec2(fo.x);
            }
#endif
            float stepScale = sceneStepScale();
            bool done = false;
#if SHADOWS == 1
            float h = probe.x * stepScale;
            if (h < 1e-4f * os_sT) {
                os_shadow = 0.0f;
                done = true;
            } else {
                os_sT += h;
                done = os_sT > os_sTmax;
            }
#else
            vec2 hp = probe * stepScale;
            float h = hp.x;
#if SHADOWS == 3
            float y = h * h / (2.0f * os_sPh);
            float dd = sqrt(max(h * h - y * y, 0.0f));
            os_sRes = min(os_sRes, k * dd / max(os_sT - y, 1e-4f));
            os_sPh = max(hp.y, 1e-6f);
#else
            os_sRes = min(os_sRes, k * h / os_sT);
#endif
            if (os_sRes < 1e-3f) {
                os_shadow = 0.0f;
                done = true;
            } else {
                os_sT += shadowStep(h, os_sT, os_sRes, k, hp.y);
                done = os_sT > os_sTmax;
            }
#endif
            if (!done && ++os_i >= u_shadowSteps) done = true;
            if (done) {
#if SHADOWS != 1
                if (os_shadow != 0.0f) os_shadow = saturate(os_sRes);
#endif
                osBeginAo();
            }
        } else {   // OS_AO (ambientOcclusion)
            float denom = max(float(u_aoSamples - 1), 1.0f);
            int i = osAoProbe(os_i);
            float h = 0.01f + 0.15f * float(i) / denom;
            float d = near * sceneStepScale();
            bool open = false;
#if AO_FARTHEST_FIRST
            if (os_i == 0) {
                if (d >= h) open = true;
                else os_aFar = h - d;
            } else {
                os_aOcc += (h - d) * os_aW;
                os_aW *= 0.9f;
            }
#else
            os_aOcc += (h - d) * os_aW;
            os_aW *= 0.9f;
#endif
            if (open) {
                os_occlusion = 1.0f;
                os_phase = OS_SHADE;
            } else if (++os_i >= u_aoSamples) {
#if AO_FARTHEST_FIRST
                os_aOcc += os_aFar * os_aW;
#endif
                os_occlusion = saturate(1.0f - 15.0f * os_aOcc / max(float(u_aoSamples), 1.0f));
                os_phase = OS_SHADE;
            }
        }
    }
    return vec4(os_col, 1.0f);
}
#endif

#endif
