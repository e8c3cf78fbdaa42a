// shade.glsl - what a ray's hit shows (GLSL and C++, included by render.glsl after the march and
// the normals): the sky a miss sees, a surface's light from its shadow and occlusion, the shadow
// ray and AO that find them (with BOUNCE_LIGHT and BOUNCE_BOUND for a reflection's surface), fog,
// and the display colour a pixel is written in.
#ifndef SDF_RENDER_SHADE_GLSL
#define SDF_RENDER_SHADE_GLSL

// What a ray that hits nothing sees.
vec3 background(vec3 rd) {
#if FOG
    return skyColor(rd, u_lightDir, u_lightColor);
#else
    return mix(vec3(0.02f, 0.02f, 0.025f), vec3(0.08f, 0.09f, 0.11f), saturate(rd.y * 0.5f + 0.5f));
#endif
}

// Direct light and ambient at a surface whose shadow (1 lit .. 0) and occlusion (1 open) are known.
vec3 litSurface(vec3 n, vec3 rd, vec3 albedo, float shadow, float occlusion) {
    vec3 l = u_lightDir;
    vec3 v = -rd;
#if PBR
    vec3 col = cookTorrance(n, v, l, albedo, u_metalness, u_roughness) * u_lightColor * (PI * shadow);
    col += ambientLight(n) * albedo * (1.0f - 0.8f * u_metalness) * occlusion;
#else
    vec3 col = albedo * (lambert(n, l) * shadow * u_lightColor + ambientLight(n) * occlusion);
#if SPECULAR
    if ((u_effectsOff & EFFECT_OFF_SPECULAR) == 0) col += u_lightColor * (blinnPhong(n, l, v, roughnessToShininess(u_roughness)) * shadow *
                           (1.0f - 0.7f * u_roughness));
#endif
#endif
    return col;
}

// Linear radiance to the display colour: tone mapped, sRGB (supersample.glsl averages these).
vec3 displayColor(vec3 col) { return linearToSRGB(toneMapACES(col)); }

// The shadow ray SHADOWS asks for (1 hard, 2 soft, 3 improved soft) along l over the range sr; a soft
// one from res0 (shadowSoftFrom: above 1, a lit ray tells by how much).
float shadowTrace(vec3 ro, vec3 l, vec2 sr, float res0) {
#if SHADOWS == 1
    return shadowHard(ro, l, sr.x, sr.y, u_shadowSteps);
#elif SHADOWS == 3
    return shadowSoftImproved(ro, l, sr.x, sr.y, u_shadowSteps, u_shadowK);
#else
    return shadowSoftFrom(ro, l, sr.x, sr.y, u_shadowSteps, u_shadowK, res0);
#endif
}

// Direct light plus ambient at a surface point (linear radiance); bounce > 0: a surface a
// reflection met (BOUNCE_LIGHT, BOUNCE_BOUND). before, weight: the pixel's radiance so far and
// what the mirror passes of this surface's (BOUNCE_BOUND).
vec3 shadeSurface(vec3 p, vec3 n, vec3 rd, vec3 albedo, float t, int bounce, vec3 before, vec3 weight) {
    bool wantShadow = true, wantOcclusion = true;
#if BOUNCE_BOUND > 0 && BOUNCE_LIGHT < 2
    if (bounce > 0) {
        // What the two terms could move the pixel by: the light with both at 1 against both at 0
        // (terms of one sign, so any values lie between), shown over the colour so far.
        vec3 spread = displayColor(before + weight * litSurface(n, rd, albedo, 1.0f, 1.0f)) -
                      displayColor(before + weight * litSurface(n, rd, albedo, 0.0f, 0.0f));
        wantShadow = wantOcclusion = max(spread.x, max(spread.y, spread.z)) > float(BOUNCE_BOUND) / 255.0f;
    }
#endif
    vec3 l = u_lightDir;
    float shadow = 1.0f;
    vec3 ro = p + n * (2.0f * hitEpsilon(t));
    // Every direct term (Lambert, Blinn-Phong, Cook-Torrance) carries max(n.l, 0), so a surface
    // turned away from the light needs no shadow ray: skipping it changes no pixel.
    bool facesLight = dot(n, l) > 0.0f && (BOUNCE_LIGHT < 2 || bounce == 0);
    // What this surface's shadow ray and AO found (-1: not traced); a frame pixel's primary hit may
    // borrow its quad centre's (quad_reflections.glsl QUAD_SHADE), whose pass keeps what it found.
    vec2 traced = vec2(-1.0f);
    vec2 lent = vec2(-1.0f);
    bool probeOcclusion = true;
#if USE_QUAD_SHADE
    if (bounce == 0) lent = g_shadeLent;
    if (g_quadPass && bounce == 0) {   // the quads' pass traces only what its centre lends
        facesLight = facesLight && (QUAD_SHADE & 6) != 0;
        probeOcclusion = (QUAD_SHADE & 1) != 0;
    }
#endif
    WORK_PHASE(bounce == 0 ? 2 : 6);
#if SHADOWS
    if (lent.x >= 0.0f) {
        shadow = lent.x;
    } else {
        vec2 sr = shadowRange(ro, l, 0.01f, u_maxDist, SHADOWS == 1 ? 1e6f : u_shadowK);
        if (facesLight && (u_effectsOff & EFFECT_OFF_SHADOWS) == 0 && sr.x <= sr.y) {
            float res0 = 1.0f;
#if USE_QUAD_SHADE && SHADOWS == 2
            if (g_quadPass && bounce == 0 && (QUAD_SHADE & 2) != 0) res0 = QUAD_SHADE_LIT;   // how lit the centre is
#endif
            traced.x = wantShadow ? shadowTrace(ro, l, sr, res0) : 0.5f;
            shadow = saturate(traced.x);
        }
    }
#endif
    float occlusion = 1.0f;
    WORK_PHASE(bounce == 0 ? 3 : 7);
#if AO
    if (lent.y >= 0.0f) occlusion = lent.y;
    else if (probeOcclusion && (u_effectsOff & EFFECT_OFF_AO) == 0 && (BOUNCE_LIGHT < 1 || bounce == 0)) occlusion = traced.y = wantOcclusion ? ambientOcclusion(p, n, u_aoSamples) : 0.5f;
#endif
#if USE_QUAD_SHADE
    if (bounce == 0) g_shadeSeen = traced;
#endif
    return litSurface(n, rd, albedo, shadow, occlusion);
}

// Shaded colour of one marched ray, with fog.
vec3 shadeRay(vec3 ro, vec3 rd, Hit h, vec3 n, int bounce, vec3 before, vec3 weight) {
    if (!h.hit) return background(rd);
    vec3 col = shadeSurface(ro + rd * h.t, n, rd, h.albedo, h.t, bounce, before, weight);
#if FOG
    if ((u_effectsOff & EFFECT_OFF_FOG) == 0) col = applyFog(col, h.t, background(rd), 0.03f);
#endif
    return col;
}

// Tiny per-pixel dither (+-0.5 / 255) against banding in 8-bit output; deterministic
// per frame so replays match.
float ditherNoise(vec2 fragCoord) {
    return fract(52.9829189f * fract(0.06711056f * fragCoord.x + 0.00583715f * fragCoord.y +
                                     0.1f * float(u_frame % 16))) - 0.5f;
}

// The pixel's output: its display colour, dithered.
vec4 pixelColor(vec3 display, vec2 fragCoord) { return vec4(display + vec3(ditherNoise(fragCoord) / 255.0f), 1.0f); }

#endif
