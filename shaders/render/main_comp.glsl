// main_comp.glsl - compute-shader entry point (GLSL only): one invocation per pixel in
// 8x8 groups (WORKGROUP_X/Y), dispatch ceil(w/8) x ceil(h/8); writes image unit 0 (rgba8). Row 0 of the
// image is the bottom row, as with the fragment path (fragCoord has the same meaning).
// DEBUG_VIEW 4 and 5 (accuracy bench, NaN scans) write an rgba32f image instead.
//
// The cone pre-pass (render.glsl's coneStart; Quality::conePrepass): u_conePass 1 is a dispatch
// of one invocation per 8x8 tile, ceil(w/64) x ceil(h/64) groups, that writes each tile's start
// distance into image unit 1 (r32f, ceil(w/8) x ceil(h/8)); u_conePass 2 is the frame, every
// primary ray starting at its tile's distance; 0 is the frame from the eye, no pre-pass.
// CONE_PREPASS 0 (the quick tier of a tiered compile, QuickTierText) leaves coneStart out of the
// program: one map() call site less to compile; its tiles then start at 0, from the eye.
//
// Shared visibility (SHARED_VISIBILITY 1: compiled in where the GPU is hardware; u_shareVisibility 1,
// Quality::shareVisibility, turns the sharing on; 0 has every pixel trace its own in the same code): shadows and AO are traced
// from one pixel of each 2x2 quad of the group (its even x, even y corner, and the group's last
// column and row) and the other pixels interpolate their representatives' (shadow, occlusion) bilinearly, each representative
// counted only where it lies on the pixel's own surface (normals within 18 degrees, within 1 % of
// the pixel's distance of its tangent plane). A pixel no representative stands for (silhouettes,
// creases) traces its own. The work is compacted in the group's shared memory, so the invocations
// that trace are the first ones: a quarter of the group's warps do the work of all of them.
// Normals, albedo and the lighting stay per pixel; only (shadow, occlusion) is shared.
#ifndef CONE_PREPASS
#define CONE_PREPASS 1
#endif
// The work-group size: 8x8 unless the scene defines WORKGROUP_X / WORKGROUP_Y (FrameRenderer reads
// it back from the program and sizes both dispatches by it).
#ifndef WORKGROUP_X
#define WORKGROUP_X 8
#endif
#ifndef WORKGROUP_Y
#define WORKGROUP_Y 8
#endif
layout(local_size_x = WORKGROUP_X, local_size_y = WORKGROUP_Y) in;
#if DEBUG_VIEW >= 4
layout(rgba32f, binding = 0) uniform writeonly image2D u_output;
#else
layout(rgba8, binding = 0) uniform writeonly image2D u_output;
#endif
layout(r32f, binding = 1) uniform image2D u_coneStart;
uniform int u_conePass;
uniform int u_shareVisibility;
const int CONE_TILE = 8;

#ifndef SHARED_VISIBILITY
#define SHARED_VISIBILITY 1   // 0 compiles the shared path out (a scene copy for `gpu.sh measure vis`)
#endif
#define USE_SHARED_VISIBILITY (SHARED_VISIBILITY && DEBUG_VIEW == 0 && !USE_SUPERSAMPLE && (SHADOWS != 0 || AO != 0))
#if USE_SHARED_VISIBILITY
const uint GROUP_SIZE = uint(WORKGROUP_X * WORKGROUP_Y);
shared vec4 s_point[GROUP_SIZE];    // a pixel's hit point and t (-1: it sees no surface)
shared vec3 s_normal[GROUP_SIZE];
shared vec2 s_visibility[GROUP_SIZE];
shared uint s_work[GROUP_SIZE];     // the pixels that trace, compacted
shared uint s_count;
shared uint s_refined;              // the pixels whose representatives disagree, compacted after them
#ifndef VISIBILITY_SPREAD
#define VISIBILITY_SPREAD 0.05   // the largest spread of shadow or occlusion between the representatives a pixel interpolates
#endif

// Whether the visibility at surface point b (its normal nb) can stand for a's: the same surface,
// near a's tangent plane and facing the same way.
float standsFor(vec4 a, vec3 na, vec4 b, vec3 nb) {
    return b.w >= 0.0 && dot(na, nb) > 0.99 && abs(dot(b.xyz - a.xyz, na)) <= 0.01 * a.w ? 1.0 : 0.0;
}

// The pixel's linear radiance with shared visibility; every invocation of the group calls it
// (barriers), `inside` false for those past the frame's edge.
vec4 renderShared(ivec2 pixel, bool inside, float tStart) {
    callSceneSetup();
    uint li = gl_LocalInvocationIndex;
    ivec2 lp = ivec2(gl_LocalInvocationID.xy);
    vec3 rd = cameraRay(vec2(pixel) + 0.5);
    Hit h = Hit(u_maxDist, 0.0, false, vec3(0.0));
    vec3 n = vec3(0.0, 1.0, 0.0);
    if (inside) {
        h = march(u_camPos, rd, tStart);
        if (h.hit) n = surfaceNormal(u_camPos + rd * h.t, h.t);
    }
    vec4 me = vec4(u_camPos + rd * h.t, h.hit ? h.t : -1.0);
    if (li == 0u) {
        s_count = 0u;
        s_refined = 0u;
    }
    s_point[li] = me;
    s_normal[li] = n;
    memoryBarrierShared();
    barrier();
    // The representatives around this pixel: the group's even columns and rows and its last ones
    // (so no pixel extrapolates past the group's edge); a pixel between two interpolates them.
    int x0 = lp.x == WORKGROUP_X - 1 ? lp.x : lp.x & ~1, y0 = lp.y == WORKGROUP_Y - 1 ? lp.y : lp.y & ~1;
    int x1 = x0 == lp.x ? x0 : lp.x + 1, y1 = y0 == lp.y ? y0 : lp.y + 1;
    uint r00 = uint(y0 * WORKGROUP_X + x0), r10 = uint(y0 * WORKGROUP_X + x1);
    uint r01 = uint(y1 * WORKGROUP_X + x0), r11 = uint(y1 * WORKGROUP_X + x1);
    vec4 w = vec4(0.0);
    bool own = false;
    if (me.w >= 0.0) {
        own = u_shareVisibility == 0 || r00 == li;
        if (!own) {
            w = vec4(standsFor(me, n, s_point[r00], s_normal[r00]), standsFor(me, n, s_point[r10], s_normal[r10]),
                     standsFor(me, n, s_point[r01], s_normal[r01]), standsFor(me, n, s_point[r11], s_normal[r11]));
            own = dot(w, vec4(1.0)) == 0.0;
        }
    }
    if (own) s_work[atomicAdd(s_count, 1u)] = li;
    memoryBarrierShared();
    barrier();
    if (li < s_count) {
        uint j = s_work[li];
        vec4 q = s_point[j];
        s_visibility[j] = surfaceVisibility(q.xyz, s_normal[j], q.w);
    }
    memoryBarrierShared();
    barrier();
    // Where the representatives disagree (a shadow's edge, a crease's AO) the pixel traces its own.
    bool refine = false;
    if (me.w >= 0.0 && !own) {
        vec2 lo = vec2(2.0), hi = vec2(-1.0);
        if (w.x > 0.0) { lo = min(lo, s_visibility[r00]); hi = max(hi, s_visibility[r00]); }
        if (w.y > 0.0) { lo = min(lo, s_visibility[r10]); hi = max(hi, s_visibility[r10]); }
        if (w.z > 0.0) { lo = min(lo, s_visibility[r01]); hi = max(hi, s_visibility[r01]); }
        if (w.w > 0.0) { lo = min(lo, s_visibility[r11]); hi = max(hi, s_visibility[r11]); }
        refine = any(greaterThan(hi - lo, vec2(VISIBILITY_SPREAD)));
    }
    if (refine) s_work[atomicAdd(s_refined, 1u)] = li;
    memoryBarrierShared();
    barrier();
    if (li < s_refined) {
        uint j = s_work[li];
        vec4 q = s_point[j];
        s_visibility[j] = surfaceVisibility(q.xyz, s_normal[j], q.w);
    }
    memoryBarrierShared();
    barrier();
    if (!inside) return vec4(0.0);
    vec2 vis = vec2(-1.0);
    if (me.w >= 0.0) {
        vis = own || refine ? s_visibility[li]
                            : (w.x * s_visibility[r00] + w.y * s_visibility[r10] + w.z * s_visibility[r01] + w.w * s_visibility[r11]) /
                                  dot(w, vec4(1.0));
    }
#if REFLECTIONS == 0
    return vec4(shadeRay(u_camPos, rd, h, n, vis), 1.0);   // traceRay's loop would be a second copy of it all
#else
    return traceRay(u_camPos, rd, 0.0, h, true, n, vis);
#endif
}
#endif

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (u_conePass == 1) {
        ivec2 tiles = (ivec2(u_resolution) + CONE_TILE - 1) / CONE_TILE;
        if (pixel.x >= tiles.x || pixel.y >= tiles.y) return;
        vec2 lo = vec2(pixel * CONE_TILE) + 0.5;
        vec2 hi = min(lo + float(CONE_TILE - 1), u_resolution - 0.5);
#if USE_SUPERSAMPLE
        lo -= 0.5;   // the samples reach the tile's pixels' edges
        hi += 0.5;
#endif
#if CONE_PREPASS
        imageStore(u_coneStart, pixel, vec4(coneStart(lo, hi)));
#else
        imageStore(u_coneStart, pixel, vec4(0.0));
#endif
        return;
    }
    bool inside = pixel.x < int(u_resolution.x) && pixel.y < int(u_resolution.y);
    vec2 fragCoord = vec2(gl_GlobalInvocationID.xy) + 0.5;
    float tStart = inside && u_conePass == 2 ? imageLoad(u_coneStart, pixel / CONE_TILE).x : 0.0;
#if USE_SHARED_VISIBILITY
    // Every invocation of the group runs it (its barriers); u_shareVisibility 0 makes every pixel
    // trace its own. No second path: each map() call site is code the driver compiles and the
    // GPU's instruction cache holds.
    vec4 c = renderShared(pixel, inside, tStart);
    if (inside) imageStore(u_output, pixel, pixelColor(displayColor(c.rgb), fragCoord));
#else
    if (!inside) return;
    imageStore(u_output, pixel, renderPixel(fragCoord, tStart));
#endif
}
