// quad_reflections.glsl - the `quad_reflections` effect's switches, the state its passes share and
// the frame pixel's look-up of its quad's bounce (GLSL only; included by render.glsl before
// traceRay, which runs the passes: main_comp.glsl dispatches them).
#ifndef SDF_RENDER_QUAD_REFLECTIONS_GLSL
#define SDF_RENDER_QUAD_REFLECTIONS_GLSL

// QUAD_REFLECTIONS 1 (the `quad_reflections` effect; compute path, one bounce): the mirror bounce is
// traced once per 2x2 pixels, through the quad's centre, by a dispatch of its own before the frame
// (main_comp.glsl, u_conePass 4 and 5), and each pixel weights what that ray saw by its own Fresnel
// term. A frame drawn 2x2 supersampled (`--render-scale 2`, the 7680x4320 show) so reflects at the
// shown pixel's rate. Elsewhere (the fragment path, debug views, more bounces) it draws as without.
#ifndef QUAD_REFLECTIONS
#define QUAD_REFLECTIONS 0
#endif
// QUAD_REFLECTIONS_OWN: where a pixel's surface is not the quad centre's, 1 (default) the pixel
// traces its own bounce, 0 it takes the centre's bounce all the same. QUAD_REFLECTIONS_COS: the
// least cosine between the two normals that still counts as the centre's surface.
// QUAD_REFLECTIONS_NEAR 1 (default): before its own bounce, such a pixel asks the three quads
// beside it on its side (its surface is often theirs); 0 asks its own quad alone.
#ifndef QUAD_REFLECTIONS_OWN
#define QUAD_REFLECTIONS_OWN 1
#endif
#ifndef QUAD_REFLECTIONS_COS
#define QUAD_REFLECTIONS_COS 0.99f
#endif
#ifndef QUAD_REFLECTIONS_NEAR
#define QUAD_REFLECTIONS_NEAR 1
#endif
// QUAD_REFLECTIONS_DEFER 1 (a scene's choice; mandelbulb's): a pixel that finds no quad's bounce to
// take does not trace its own in the frame, where its warp's other lanes would wait for it; the
// frame appends it to a list and a dispatch of its own (u_conePass 6, sized by the list) traces the
// listed bounces side by side and writes their pixels. Past the list's room (FrameRenderer: an
// eighth of the pixels) a pixel traces its own in the frame, as with 0 (the default). One pixel, one
// picture: the same trace either way. It pays only where many pixels are listed: the list's
// dispatch runs after the frame with nothing beside it, so its longest bounce is a wait the frame
// would have hidden (an H200 at 7680x4320: mandelbulb 9.10 -> 8.63 ms, character 2.58 -> 5.27).
#ifndef QUAD_REFLECTIONS_DEFER
#define QUAD_REFLECTIONS_DEFER 0
#endif
// QUAD_SHADE (with quad_reflections; bits): the quads' pass also lends what its centre's surface
// found to the frame pixels on that surface, which then trace none of it themselves:
//   1 its ambient occlusion;
//   2 its soft shadow ray's "lit", where every sample's penumbra term k h / t was QUAD_SHADE_LIT or
//     more (a ray half a pixel beside it is lit too);
//   4 a shadow blended from the four centres around the pixel (its quad's and the three beside it on
//     its side, weighed by nearness), where all four are on its surface and found shadows within
//     QUAD_SHADE_SPREAD of each other: a penumbra's or a shadow's inside, not its edge.
// 7 (all three) by default: on an H100 it takes 8-21 % off the 7680x4320 show of every scene but
// mandelbulb (docs/performance.md, session 50), whose folds borrow in scattered pixels and whose
// header keeps 1; 0: every pixel traces its own. On the centre's surface: the pixel's normal within QUAD_REFLECTIONS_COS
// of the centre's, and its hit within two hit thresholds and two pixel footprints of the centre's
// tangent plane (a step's lower side does not borrow the upper's light). In the 7680x4320 show the
// primary hits' AO and most of their shadow rays are so traced once per shown pixel, as the bounce
// is; the four samples keep their own march, normal and material, and a shadow's edge its own
// shadow rays (lending those too, the centre's shadow alone, drew the edges jagged: 1-2 % of
// llvmpipe's shown pixels moved past 8/255).
// QUAD_SHADE_ALONE 1: a frame with no reflection bounce runs the quads' pass for the light alone
// (`bench --tests full_quad_shade`). Off: at one sample a pixel it lost on the H100 (field150 at
// 3840x2160 1.385 -> 1.427 ms, mandelbulb 1.343 -> 1.691), the pass costing more than it lends.
#ifndef QUAD_SHADE
#define QUAD_SHADE 7
#endif
#ifndef QUAD_SHADE_ALONE
#define QUAD_SHADE_ALONE 0
#endif
#ifndef QUAD_SHADE_LIT
#define QUAD_SHADE_LIT 1.25f
#endif
#ifndef QUAD_SHADE_SPREAD
#define QUAD_SHADE_SPREAD 0.1f
#endif
#if QUAD_REFLECTIONS && defined(SDFVJ_COMPUTE) && (DEBUG_VIEW == 0 || WORK_VIEW) && (REFLECTIONS == 1 || (REFLECTIONS == 0 && QUAD_SHADE != 0 && QUAD_SHADE_ALONE != 0))
#define USE_QUAD_REFLECTIONS 1
#else
#define USE_QUAD_REFLECTIONS 0
#endif
#if USE_QUAD_REFLECTIONS && REFLECTIONS == 1 && QUAD_REFLECTIONS_DEFER && QUAD_REFLECTIONS_OWN && SUPERSAMPLE == 0
#define USE_QUAD_DEFER 1
#else
#define USE_QUAD_DEFER 0
#endif

#if USE_QUAD_REFLECTIONS && QUAD_SHADE != 0
#define USE_QUAD_SHADE 1
#else
#define USE_QUAD_SHADE 0
#endif

#if USE_QUAD_REFLECTIONS
// One texel per 2x2 pixels: what the centre's bounce saw (halves r g | b, then the centre's shadow
// and occlusion as 8 bits each: quadTexel), the centre's normal (octahedral, snorm 16) and its depth
// (float; -1 for the sky).
layout(rgba32ui, binding = 2) uniform uimage2D u_quadReflections;
bool g_quadPass = false;   // the quads' own dispatch: traceRay shades only the bounce, into g_bounceLight
vec3 g_bounceLight = vec3(0.0f);
float g_firstT = -1.0f;    // the primary hit's distance (-1: the sky) and normal: the quads' pass stores
vec3 g_firstN = vec3(0.0f, 1.0f, 0.0f);   // the centre's, the frame compares a pixel's with them
ivec2 g_pixel = ivec2(0);  // the frame's pixel (main_comp.glsl)
bool g_deferPass = false;  // the list's dispatch (QUAD_REFLECTIONS_DEFER): traceRay starts at the bounce
uvec4 g_quad = uvec4(0u);  // the frame pixel's quad (quadFind), and whether its surface is the centre's
bool g_quadFound = false;
vec2 g_shadeSeen = vec2(-1.0f);   // the quads' pass: the centre's shadow and occlusion (-1: not traced)
vec2 g_shadeLent = vec2(-1.0f);   // the frame's primary hit: its quad's (-1: the pixel traces its own)

// The quads' pass's texel for its centre. Its shadow in 8 bits: 0..253 what its ray found, 254 lit
// by QUAD_SHADE_LIT or more, 255 none traced; its occlusion: 0..254, 255 none.
uvec4 quadTexel(vec3 bounceLight, float t, vec3 n, vec2 shade) {
    uvec2 s = uvec2(shade.x >= QUAD_SHADE_LIT ? 254u : shade.x < 0.0f ? 255u : uint(round(saturate(shade.x) * 253.0f)),
                    shade.y < 0.0f ? 255u : uint(round(saturate(shade.y) * 254.0f)));
    return uvec4(packHalf2x16(bounceLight.rg), (packHalf2x16(vec2(bounceLight.b, 0.0f)) & 0xffffu) | (s.x << 16) | (s.y << 24),
                 packSnorm2x16(octEncode(n)), floatBitsToUint(t));
}
float quadShadow(uint s) { return s == 255u ? -1.0f : s == 254u ? 1.0f : float(s) / 253.0f; }

// The quads around the frame pixel: k 0 its own, 1 and 2 the ones beside it on its side across and
// up or down, 3 the one diagonally beside (clamped to this frame's quads).
ivec2 quadNear(int k) {
    ivec2 side = (g_pixel & 1) * 2 - 1;
    ivec2 q = (g_pixel >> 1) + (k == 1 ? ivec2(side.x, 0) : k == 2 ? ivec2(0, side.y) : k == 3 ? side : ivec2(0));
    return clamp(q, ivec2(0), (ivec2(u_resolution) + 1) / 2 - 1);
}

// Whether the frame pixel's primary hit p (depth g_firstT, normal g_firstN) is on the surface of
// the centre of quad q (its depth tc and normal nc): its normal within QUAD_REFLECTIONS_COS of the
// centre's, and p within two hit thresholds and two pixel footprints of the centre's tangent plane.
bool quadOnSurface(float tc, vec3 nc, ivec2 q, vec3 p) {
    vec3 pc = u_camPos + cameraRay(vec2(q * 2) + 1.0f) * tc;
    return tc > 0.0f && dot(nc, g_firstN) >= QUAD_REFLECTIONS_COS &&
           abs(dot(p - pc, nc)) <= 2.0f * (hitEpsilon(g_firstT) + g_firstT * pixelAngle());
}

// QUAD_SHADE 4: the frame pixel's shadow blended bilinearly from the four quad centres around it
// (its own and those beside it on its side, weighed 9 3 3 1 by nearness), where all four are on its
// surface, traced a shadow ray and found values within QUAD_SHADE_SPREAD of each other (a penumbra's
// or a shadow's inside, not its edge); -1 elsewhere.
float quadShadowBlend(vec3 p) {
    float lo = 2.0f, hi = -2.0f, sum = 0.0f;
    for (int k = 0; k < 4; k++) {
        ivec2 q = quadNear(k);
        uvec4 quad = imageLoad(u_quadReflections, q);
        float v = quadShadow((quad.y >> 16) & 0xffu);
        if (v < 0.0f || !quadOnSurface(uintBitsToFloat(quad.w), octDecode(unpackSnorm2x16(quad.z)), q, p)) return -1.0f;
        lo = min(lo, v), hi = max(hi, v);
        sum += v * (k == 0 ? 9.0f : k == 3 ? 1.0f : 3.0f);
    }
    return hi - lo <= QUAD_SHADE_SPREAD ? sum / 16.0f : -1.0f;
}

// The frame pixel's primary hit at p (its g_firstT, g_firstN set): finds the quad whose centre's
// surface it is on, for its bounce (quadBounceSeen) and its light (g_shadeLent, QUAD_SHADE). For
// the bounce: a pixel whose depth is 2 % or more off the centre's, the centre seeing the sky, or
// whose normal turned more than about 8 degrees from the centre's is not on it. With
// QUAD_REFLECTIONS_NEAR 1 (the default) the pixel asks its own quad, then the three beside it on its
// side: an edge's pixel is often the neighbour's surface, and a fold's normal often a neighbour's.
// For the light (QUAD_SHADE; p is read for nothing else), the quad found must also pass quadOnSurface.
// The quad found returns from inside the loop: breaking out of it to shared code after (the same
// picture) drew character's 7680x4320 show in 4.63 ms against 2.27 on an H100, driver 580, with
// field150 and midi 1-3 % faster (docs/performance.md, session 51).
void quadFind(vec3 p) {
    for (int k = 0; k < (QUAD_REFLECTIONS_NEAR != 0 ? 4 : 1); k++) {
        ivec2 q = quadNear(k);
        uvec4 quad = imageLoad(u_quadReflections, q);
        float tc = uintBitsToFloat(quad.w);
        vec3 nc = octDecode(unpackSnorm2x16(quad.z));
        if (abs(tc - g_firstT) <= 0.02f * g_firstT && dot(nc, g_firstN) >= QUAD_REFLECTIONS_COS) {
            g_quad = quad, g_quadFound = true;
#if USE_QUAD_SHADE
            if (quadOnSurface(tc, nc, q, p)) {
                uvec2 s = uvec2((quad.y >> 16) & 0xffu, quad.y >> 24);
                g_shadeLent = vec2((QUAD_SHADE & 2) != 0 && s.x == 254u ? 1.0f : -1.0f,
                                   (QUAD_SHADE & 1) != 0 && s.y != 255u ? float(s.y) / 254.0f : -1.0f);
            }
#if (QUAD_SHADE & 4) != 0
            if (g_shadeLent.x < 0.0f) g_shadeLent.x = quadShadowBlend(p);
#endif
#endif
            return;
        }
    }
#if USE_QUAD_SHADE && (QUAD_SHADE & 4) != 0
    g_shadeLent.x = quadShadowBlend(p);
#endif
    // QUAD_REFLECTIONS_OWN 0: the pixel takes its own quad's bounce all the same (not its light)
    if (QUAD_REFLECTIONS_OWN == 0) g_quad = imageLoad(u_quadReflections, quadNear(0)), g_quadFound = true;
}

// What the quads' pass saw for this frame pixel's bounce, or -1 where it traces its own (its surface
// is not its quad's centre's: quadFind; QUAD_REFLECTIONS_OWN 1, the default).
vec3 quadBounceSeen() {
    if (!g_quadFound) return vec3(-1.0f);
    return vec3(unpackHalf2x16(g_quad.x), unpackHalf2x16(g_quad.y).x);
}
#endif
#if USE_QUAD_DEFER
// The list of bounces left for their own dispatch (main_comp.glsl): the frame appends, returning
// false where the list is full; the listed pixel's trace resumes from what was left in it.
bool quadDeferPush(ivec2 pixel, vec3 ro, vec3 rd, float tNext, vec3 throughput, vec3 col);
bool g_deferred = false;   // the frame's pixel is in the list: the dispatch of the list writes it
vec3 g_deferRo, g_deferRd, g_deferThroughput, g_deferCol;
float g_deferTNext;
#endif

#endif
