// shading.glsl - everything that looks at the scene from a surface point: normals,
// shadows, ambient occlusion, lighting models, sky/fog, tone mapping, debug colours.
//
// Include it AFTER the scene: it calls the scene's `vec4 map(vec3 p)` (albedo, distance)
// and `float sceneLipschitz()`, dividing distances by the latter so shadow and AO probes
// stay valid on twisted or displaced fields.
// Usage: vec3 n = calcNormalTetra(p, 1e-3f);
//        float s = shadowSoftImproved(p + n * 2e-3f, l, 0.01f, 20.0f, 64, 8.0f);
//        vec3 c = cookTorrance(n, v, l, albedo, metalness, roughness) * lightColor * s;
//        vec3 display = linearToSRGB(toneMapACES(c));
#ifndef SDF_LIB_SHADING_GLSL
#define SDF_LIB_SHADING_GLSL
#include "lib/common.glsl"

// The field the probes below sample. A renderer may point it at a cheaper field that is
// still a distance bound (render.glsl: mapNear, the ground alone far from the objects).
#ifndef PROBE_MAP
#define PROBE_MAP map
#endif

// What a shadow ray from ro along rd reads at t (k: its penumbra hardness; a hard shadow passes 1e4,
// its hit test h < 1e-4 t being k h / t < 1): x, the field there (its penumbra term); y >= x, a
// distance the soft shadows' safe step may take as the field's (shadowStep). By default both are
// the probed field; a renderer that knows more sets y (render.glsl shadowProbe: past the floor's
// blend, the distance to the objects).
#ifndef SHADOW_PROBE
#define SHADOW_PROBE(ro, rd, t, k) vec2(PROBE_MAP((ro) + (rd) * (t)).w)
#endif

// 1 / (the step correction the scene asks for)
float sceneStepScale() { return 1.0f / max(1.0f, sceneLipschitz()); }

// ---- normals --------------------------------------------------------------------------
// Central differences: 6 map calls, second-order accurate. The normals below are loops from
// SDF_LOOP_ZERO (lib/common.glsl): one map() call site each.
vec3 calcNormalCentral(vec3 p, float eps) {
    vec3 n = vec3(0.0f);
    for (int i = SDF_LOOP_ZERO; i < 6; i++) {   // +x, -x, +y, -y, +z, -z
        float sg = (i & 1) == 0 ? 1.0f : -1.0f;
        vec3 axis = vec3(i < 2 ? 1.0f : 0.0f, i == 2 || i == 3 ? 1.0f : 0.0f, i > 3 ? 1.0f : 0.0f);
        n += axis * (sg * PROBE_MAP(p + axis * (sg * eps)).w);
    }
    return safeNormalize(n);
}

// Forward differences: 4 map calls, first-order accurate.
vec3 calcNormalForward(vec3 p, float eps) {
    float d = PROBE_MAP(p).w;
    return safeNormalize(vec3(PROBE_MAP(p + vec3(eps, 0.0f, 0.0f)).w - d,
                              PROBE_MAP(p + vec3(0.0f, eps, 0.0f)).w - d,
                              PROBE_MAP(p + vec3(0.0f, 0.0f, eps)).w - d));
}

// Forward differences from d, the field's value at p where the caller already has it (a march
// reads it at its hit): 3 map calls, one call site (a rolled loop).
vec3 calcNormalForwardFrom(vec3 p, float eps, float d) {
    vec3 n = vec3(0.0f);
    for (int i = SDF_LOOP_ZERO; i < 3; i++) {   // +x, +y, +z
        vec3 axis = vec3(i == 0 ? 1.0f : 0.0f, i == 1 ? 1.0f : 0.0f, i == 2 ? 1.0f : 0.0f);
        n += axis * (PROBE_MAP(p + axis * eps).w - d);
    }
    return safeNormalize(n);
}

// Tetrahedron: 4 map calls at the corners of a tetrahedron, second-order-ish accurate.
vec3 calcNormalTetra(vec3 p, float eps) {
    vec3 n = vec3(0.0f);
    for (int i = SDF_LOOP_ZERO; i < 4; i++) {   // (1,-1,-1), (-1,-1,1), (-1,1,-1), (1,1,1)
        vec3 k = vec3(float(((i + 3) >> 1) & 1) * 2.0f - 1.0f, float((i >> 1) & 1) * 2.0f - 1.0f, float(i & 1) * 2.0f - 1.0f);
        n += k * PROBE_MAP(p + k * eps).w;
    }
    return safeNormalize(n);
}

// ---- shadows: ro is the (offset) surface point, rd the unit direction to the light -----
// The soft shadows' step from t, where the field (already divided by its Lipschitz bound) reads h
// and the penumbra so far is res: iq's clamp(h, 0.005, 0.5), or further where no point can darken
// the penumbra. Within s of t the field is at least h - s, so every point there has
// k * (h - s) / (t + s) >= res while s <= (k h - res t) / (k + res): no sample skipped could have
// lowered res. hSafe (SHADOW_PROBE's y, >= h): a 1-Lipschitz lower bound, by the same argument, of
// what can still darken the ray; the safe step takes it where it is larger. SHADOW_SAFE_STEP 0:
// the clamp alone.
#ifndef SHADOW_SAFE_STEP
#define SHADOW_SAFE_STEP 1
#endif
float shadowStep(float h, float t, float res, float k, float hSafe) {
    float s = clamp(h, 0.005f, 0.5f);
#if SHADOW_SAFE_STEP
    s = max(s, (k * max(h, hSafe) - res * t) / (k + res));
#endif
    return s;
}

// Hard: 0 if anything is hit before tmax, else 1.
float shadowHard(vec3 ro, vec3 rd, float tmin, float tmax, int steps) {
    float stepScale = sceneStepScale();
    float t = tmin;
    for (int i = 0; i < steps; i++) {
        float h = SHADOW_PROBE(ro, rd, t, 1e4f).x * stepScale;
        if (h < 1e-4f * t) return 0.0f;
        t += h;
        if (t > tmax) break;
    }
    return 1.0f;
}

// Soft: penumbra from the closest miss along the ray, k = hardness (8 soft .. 64 sharp), as the
// least penumbra term k h / t of its samples, from res0 down (shadowSoft: 1, which it returns where the
// ray is lit; a larger res0 also tells by how much a lit ray was lit).
float shadowSoftFrom(vec3 ro, vec3 rd, float tmin, float tmax, int steps, float k, float res0) {
    float stepScale = sceneStepScale();
    float res = res0;
    float t = tmin;
    for (int i = 0; i < steps; i++) {
        vec2 hp = SHADOW_PROBE(ro, rd, t, k) * stepScale;
        float h = hp.x;
        res = min(res, k * h / t);
        if (res < 1e-3f) return 0.0f;
        t += shadowStep(h, t, res, k, hp.y);
        if (t > tmax) break;
    }
    return res;
}
float shadowSoft(vec3 ro, vec3 rd, float tmin, float tmax, int steps, float k) {
    return saturate(shadowSoftFrom(ro, rd, tmin, tmax, steps, k, 1.0f));
}

// Improved soft (iq): estimates the closest approach between two samples by intersecting
// their spheres, which removes the banding of shadowSoft near sharp corners.
float shadowSoftImproved(vec3 ro, vec3 rd, float tmin, float tmax, int steps, float k) {
    float stepScale = sceneStepScale();
    float res = 1.0f;
    float t = tmin;
    float ph = 1e10f;
    for (int i = 0; i < steps; i++) {
        vec2 hp = SHADOW_PROBE(ro, rd, t, k) * stepScale;
        float h = hp.x;
        float y = h * h / (2.0f * ph);
        float d = sqrt(max(h * h - y * y, 0.0f));
        res = min(res, k * d / max(t - y, 1e-4f));
        ph = max(hp.y, 1e-6f);   // the sphere the step is taken in (hp.y >= h: SHADOW_PROBE)
        if (res < 1e-3f) return 0.0f;
        t += shadowStep(h, t, res, k, hp.y);
        if (t > tmax) break;
    }
    return saturate(res);
}

// ---- ambient occlusion ------------------------------------------------------------------
// Samples the field along the normal; 1 = open, 0 = fully occluded.
//
// AO_FARTHEST_FIRST (a scene opts in: the fields do, lib/field_scene.glsl; off by default): the farthest probe goes
// first. The probed field is 1-Lipschitz (times stepScale), so when it reads d >= h there, every
// nearer probe reads d(p + n h') >= d - (h - h') >= h': none adds occlusion (each adds h' - d' <= 0),
// and the result is 1 whatever they read. Open surfaces (the floor, a convex limb) take one
// probe instead of all; an occluded one takes the same probes as before, the farthest last in
// the sum as it always was. One map() call site.
#ifndef AO_FARTHEST_FIRST
#define AO_FARTHEST_FIRST 0
#endif
float ambientOcclusion(vec3 p, vec3 n, int samples) {
    float stepScale = sceneStepScale();
    float occ = 0.0f;
    float weight = 1.0f;
    float denom = max(float(samples - 1), 1.0f);
#if AO_FARTHEST_FIRST
    float farthest = 0.0f;   // the farthest probe's h - d, added last with its weight
    for (int j = 0; j < samples; j++) {
        int i = j == 0 ? samples - 1 : j - 1;
        float h = 0.01f + 0.15f * float(i) / denom;
        float d = PROBE_MAP(p + n * h).w * stepScale;
        if (j == 0) {
            if (d >= h) return 1.0f;
            farthest = h - d;
        } else {
            occ += (h - d) * weight;
            weight *= 0.9f;
        }
    }
    occ += farthest * weight;
#else
    for (int i = 0; i < samples; i++) {
        float h = 0.01f + 0.15f * float(i) / denom;
        float d = PROBE_MAP(p + n * h).w * stepScale;
        occ += (h - d) * weight;
        weight *= 0.9f;
    }
#endif
    // normalised so 5 samples give iq's classic 1 - 3 * occ
    return saturate(1.0f - 15.0f * occ / max(float(samples), 1.0f));
}

// ---- lighting (n, l, v unit length; l towards the light, v towards the eye) -----------
float lambert(vec3 n, vec3 l) { return max(dot(n, l), 0.0f); }

// Normalised Blinn-Phong specular term (energy roughly constant across shininess).
float blinnPhong(vec3 n, vec3 l, vec3 v, float shininess) {
    vec3 h = safeNormalize(l + v);
    return (shininess + 8.0f) / (8.0f * PI) * pow(max(dot(n, h), 0.0f), shininess) * lambert(n, l);
}
// The Blinn-Phong exponent that looks like a given GGX roughness.
float roughnessToShininess(float roughness) {
    float a = max(roughness * roughness, 1e-3f);
    return clamp(2.0f / (a * a) - 2.0f, 1.0f, 4096.0f);
}

// GGX / Trowbridge-Reitz normal distribution, alpha = roughness^2.
float distributionGGX(float NdotH, float roughness) {
    float a = max(roughness * roughness, 1e-3f);
    float a2 = a * a;
    float q = NdotH * NdotH * (a2 - 1.0f) + 1.0f;
    return a2 / (PI * q * q);
}
// Smith geometry term with Schlick-GGX, k = (roughness + 1)^2 / 8 (direct lighting).
float geometrySmith(float NdotV, float NdotL, float roughness) {
    float k = (roughness + 1.0f) * (roughness + 1.0f) / 8.0f;
    return NdotV / (NdotV * (1.0f - k) + k) * (NdotL / (NdotL * (1.0f - k) + k));
}
// Fresnel-Schlick.
vec3 fresnelSchlick(float cosTheta, vec3 F0) {
    float f = pow(1.0f - saturate(cosTheta), 5.0f);
    return F0 + (vec3(1.0f) - F0) * f;
}
// Base reflectance: 0.04 for dielectrics, the albedo for metals.
vec3 baseReflectance(vec3 albedo, float metalness) {
    return mix(vec3(0.04f), albedo, metalness);
}
// Cook-Torrance BRDF times cos(theta_l): multiply by the light colour (and shadow).
vec3 cookTorrance(vec3 n, vec3 v, vec3 l, vec3 albedo, float metalness, float roughness) {
    float r = clamp(roughness, 0.03f, 1.0f);
    vec3 h = safeNormalize(v + l);
    float NdotL = max(dot(n, l), 0.0f);
    float NdotV = max(dot(n, v), 1e-4f);
    float NdotH = max(dot(n, h), 0.0f);
    vec3 F = fresnelSchlick(max(dot(h, v), 0.0f), baseReflectance(albedo, metalness));
    vec3 specular = distributionGGX(NdotH, r) * geometrySmith(NdotV, NdotL, r) * F /
                    (4.0f * NdotV * max(NdotL, 1e-4f));
    vec3 kd = (vec3(1.0f) - F) * (1.0f - metalness);
    return (kd * albedo / PI + specular) * NdotL;
}

// ---- environment ---------------------------------------------------------------------
// Hemisphere ambient: sky colour from above, warm ground bounce from below.
vec3 ambientLight(vec3 n) {
    return mix(vec3(0.10f, 0.08f, 0.06f), vec3(0.30f, 0.38f, 0.50f), 0.5f + 0.5f * n.y);
}
// Sky gradient with a sun disc and glow in the light direction.
vec3 skyColor(vec3 rd, vec3 lightDir, vec3 lightColor) {
    float y = max(rd.y, 0.0f);
    vec3 col = mix(vec3(0.55f, 0.62f, 0.72f), vec3(0.18f, 0.32f, 0.60f), sqrt(y));
    col = mix(col, vec3(0.30f, 0.28f, 0.26f), saturate(-rd.y * 4.0f));
    float sun = max(dot(rd, lightDir), 0.0f);
    col += lightColor * (0.25f * pow(sun, 8.0f) + 4.0f * pow(sun, 800.0f));
    return col;
}
// Exponential distance fog towards fogColor.
vec3 applyFog(vec3 col, float t, vec3 fogColor, float density) {
    return mix(fogColor, col, exp(-density * t));
}

// ---- display ---------------------------------------------------------------------------
// ACES filmic fit (Narkowicz 2015) and Reinhard; both expect linear radiance.
vec3 toneMapACES(vec3 x) {
    return saturate((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f));
}
vec3 toneMapReinhard(vec3 x) { return x / (x + vec3(1.0f)); }

float linearToSRGB(float c) {
    float x = saturate(c);
    return x <= 0.0031308f ? 12.92f * x : 1.055f * pow(x, 1.0f / 2.4f) - 0.055f;
}
vec3 linearToSRGB(vec3 c) {
    return vec3(linearToSRGB(c.x), linearToSRGB(c.y), linearToSRGB(c.z));
}

// Debug heatmap: 0 blue -> green -> yellow -> 1 red.
vec3 heatmap(float t) {
    float x = saturate(t);
    return saturate(vec3(1.5f - abs(4.0f * x - 3.0f), 1.5f - abs(4.0f * x - 2.0f),
                         1.5f - abs(4.0f * x - 1.0f)));
}

#endif
