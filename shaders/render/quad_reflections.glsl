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
#if QUAD_REFLECTIONS && defined(SDFVJ_COMPUTE) && DEBUG_VIEW == 0 && REFLECTIONS == 1
#define USE_QUAD_REFLECTIONS 1
#else
#define USE_QUAD_REFLECTIONS 0
#endif
#if USE_QUAD_REFLECTIONS && QUAD_REFLECTIONS_DEFER && QUAD_REFLECTIONS_OWN && SUPERSAMPLE == 0
#define USE_QUAD_DEFER 1
#else
#define USE_QUAD_DEFER 0
#endif

#if USE_QUAD_REFLECTIONS
// One texel per 2x2 pixels: what the centre's bounce saw (halves: r g, b and the centre's depth, -1
// for the sky) and the centre's normal (octahedral, snorm 16).
layout(rgba32ui, binding = 2) uniform uimage2D u_quadReflections;
bool g_quadPass = false;   // the quads' own dispatch: traceRay shades only the bounce, into g_bounceLight
vec3 g_bounceLight = vec3(0.0f);
float g_firstT = -1.0f;    // the primary hit's distance (-1: the sky) and normal: the quads' pass stores
vec3 g_firstN = vec3(0.0f, 1.0f, 0.0f);   // the centre's, the frame compares a pixel's with them
ivec2 g_pixel = ivec2(0);  // the frame's pixel (main_comp.glsl)
bool g_deferPass = false;  // the list's dispatch (QUAD_REFLECTIONS_DEFER): traceRay starts at the bounce

// What the quads' pass saw for this frame pixel's bounce, or -1 where it traces its own: a pixel
// whose surface is not the centre's (its depth 2 % or more off, the centre sees the sky, or its
// normal turned more than about 8 degrees from the centre's) traces its own (QUAD_REFLECTIONS_OWN
// 1, the default). With QUAD_REFLECTIONS_NEAR 1 (the default) it first asks the three quads beside
// it on its side the same: an edge's pixel is often the neighbour's surface, and a fold's normal
// often a neighbour's.
vec3 quadBounceSeen() {
    ivec2 side = (g_pixel & 1) * 2 - 1;
    for (int k = 0; k < (QUAD_REFLECTIONS_NEAR != 0 ? 4 : 1); k++) {
        ivec2 q = (g_pixel >> 1) + (k == 1 ? ivec2(side.x, 0) : k == 2 ? ivec2(0, side.y) : k == 3 ? side : ivec2(0));
        q = clamp(q, ivec2(0), (ivec2(u_resolution) + 1) / 2 - 1);   // this frame's quads only
        uvec4 quad = imageLoad(u_quadReflections, q);
        vec2 rg = unpackHalf2x16(quad.x), bt = unpackHalf2x16(quad.y);
        if ((QUAD_REFLECTIONS_OWN == 0 && k == 0) ||
            (abs(bt.y - g_firstT) <= 0.02f * g_firstT && dot(octDecode(unpackSnorm2x16(quad.z)), g_firstN) >= QUAD_REFLECTIONS_COS))
            return vec3(rg, bt.x);
    }
    return vec3(-1.0f);
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
