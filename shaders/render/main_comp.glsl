// main_comp.glsl - compute-shader entry point (GLSL only): one invocation per pixel in
// 8x8 groups (WORKGROUP_X/Y), dispatch ceil(w/8) x ceil(h/8); writes image unit 0 (rgba8). Row 0 of the
// image is the bottom row, as with the fragment path (fragCoord has the same meaning).
// DEBUG_VIEW 4 to 7 (accuracy bench, NaN scans, bench work) write an rgba32f image instead.
//
// The cone pre-pass (render/march.glsl's coneStart; Quality::conePrepass): u_conePass 1 is a dispatch
// of one invocation per 8x8 tile, ceil(w/64) x ceil(h/64) groups, that writes each tile's start
// distance into image unit 1 (r32f, ceil(w/8) x ceil(h/8)); u_conePass 2 is the frame, every
// primary ray starting at its tile's distance; 0 is the frame from the eye, no pre-pass; 3 (a scene
// with a frame state, without the pre-pass) is one group that only stores the scene's state.
// CONE_PREPASS 0 (the quick tier of a tiered compile, QuickTierText) leaves coneStart out of the
// program: one map() call site less to compile; its tiles then start at 0, from the eye.
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
#if DEBUG_VIEW >= 4 && DEBUG_VIEW <= 7
layout(rgba32f, binding = 0) uniform writeonly image2D u_output;
#else
layout(rgba8, binding = 0) uniform writeonly image2D u_output;
#endif
layout(r32f, binding = 1) uniform image2D u_coneStart;
uniform int u_conePass;
uniform int u_rowOffset;   // the frame drawn in strips (FrameRenderer::SetStrips): the strip's first row
const int CONE_TILE = 8;

#ifndef SCENE_SETUP_LANES
#define SCENE_SETUP_LANES 0
#endif

// Which pixel each invocation of a group draws. By default the group's invocations run row by
// row, so a 32-lane warp of a 16-wide group covers 16x2 pixels. WARP_BLOCKS 1 (on for groups
// 16 or more wide whose sides are multiples of 8 and 4) gives each run of 32 invocations an 8x4
// block instead: the same pixels, each drawn the same way, by lanes whose rays are nearer each
// other (a warp runs as long as its slowest lane) and share one cone tile. 2: 4x8 blocks.
#ifndef WARP_BLOCKS
#if WORKGROUP_X >= 16 && WORKGROUP_X % 8 == 0 && WORKGROUP_Y % 8 == 0
#define WARP_BLOCKS 1
#else
#define WARP_BLOCKS 0
#endif
#endif
ivec2 invocationPixel() {
#if WARP_BLOCKS
    const uint bw = WARP_BLOCKS == 2 ? 4u : 8u;   // the block's width; 32 / bw rows
    uint i = gl_LocalInvocationIndex, block = i >> 5u, lane = i & 31u;
    uint across = uint(WORKGROUP_X) / bw;
    uvec2 local = uvec2((block % across) * bw + lane % bw, (block / across) * (32u / bw) + lane / bw);
    return ivec2(gl_WorkGroupID.xy * gl_WorkGroupSize.xy + local);
#else
    return ivec2(gl_GlobalInvocationID.xy);
#endif
}

#if USE_QUAD_DEFER
// The bounces the frame left for their own dispatch (quad_reflections.glsl QUAD_REFLECTIONS_DEFER). The head
// is the dispatch's size (groups x, y, z: glDispatchComputeIndirect reads it), the entries counted
// and the room; FrameRenderer sets it to {0, 1, 1, 0, room} before each frame. An entry is four
// uvec4: the pixel (x | y << 16), the bounce's origin, its direction, where its march starts, the
// throughput and the colour so far, all as the frame had them (the same picture, listed or not).
// Two buffers: the head is written from the CPU each frame, the entries stay in the GPU's memory.
layout(std430, binding = 3) buffer QuadDeferred {
    uint qd_groups, qd_groupsY, qd_groupsZ, qd_count, qd_room, qd_pad0, qd_pad1, qd_pad2;
};
layout(std430, binding = 4) buffer QuadDeferredEntries {
    uvec4 qd_entries[];
};
const uint QD_GROUP = uint(WORKGROUP_X * WORKGROUP_Y);

bool quadDeferPush(ivec2 pixel, vec3 ro, vec3 rd, float tNext, vec3 throughput, vec3 col) {
    uint i = atomicAdd(qd_count, 1u);
    if (i >= qd_room) return false;
    if (i % QD_GROUP == 0u) atomicMax(qd_groups, i / QD_GROUP + 1u);
    qd_entries[4u * i] = uvec4(uint(pixel.x) | (uint(pixel.y) << 16), floatBitsToUint(ro));
    qd_entries[4u * i + 1u] = uvec4(floatBitsToUint(rd), floatBitsToUint(tNext));
    qd_entries[4u * i + 2u] = uvec4(floatBitsToUint(throughput), floatBitsToUint(col.r));
    qd_entries[4u * i + 3u] = uvec4(floatBitsToUint(col.gb), 0u, 0u);
    return true;
}
#endif

void main() {
#if SCENE_TABLES && SCENE_SETUP_LANES
    // The scene's tables (lib/common.glsl SCENE_TABLES): filled by the whole group, in shared memory.
    sceneSetupLanes(gl_LocalInvocationIndex, gl_WorkGroupSize.x * gl_WorkGroupSize.y);
    memoryBarrierShared();
    barrier();
#endif
    ivec2 pixel = invocationPixel();
#if SCENE_STATE_FRAME
    // The scene's state for the frame (lib/common.glsl SCENE_SETUP_FRAME): the cone pre-pass computes
    // it in every invocation and its first leaves it in the buffer; u_conePass 3, a dispatch of one
    // group, only that. The frame reads it as a uniform block.
    if (u_conePass == 1 || u_conePass == 3) {
        sceneSetup();
        if (pixel == ivec2(0)) sceneStateStore();
        if (u_conePass == 3) return;
    } else {
        sceneStateLoad();
    }
#endif
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
#if USE_QUAD_REFLECTIONS
    if (u_conePass == 4 || u_conePass == 5) {   // the quads' bounces (quad_reflections.glsl QUAD_REFLECTIONS): 4 after the cone pre-pass, 5 without
        if (pixel.x >= (int(u_resolution.x) + 1) / 2 || pixel.y >= (int(u_resolution.y) + 1) / 2) return;
        callSceneSetup();
        // Through the quad's centre; its pixels share one cone tile (tiles are 8 wide, quads 2).
        float tStart = u_conePass == 4 ? imageLoad(u_coneStart, pixel * 2 / CONE_TILE).x : 0.0;
        g_quadPass = true;
        Hit none = Hit(0.0, 0.0, false, vec3(0.0), 0.0);
        traceRay(u_camPos, cameraRay(vec2(pixel * 2) + 1.0), tStart, none, false);
        imageStore(u_quadReflections, pixel, quadTexel(g_bounceLight, g_firstT, g_firstN, g_shadeSeen));
        return;
    }
#endif
#if USE_QUAD_DEFER
    if (u_conePass == 6) {   // the listed bounces (quad_reflections.glsl QUAD_REFLECTIONS_DEFER), one an invocation
        uint i = gl_WorkGroupID.x * QD_GROUP + gl_LocalInvocationIndex;
        if (i >= min(qd_count, qd_room)) return;
        uvec4 a = qd_entries[4u * i], b = qd_entries[4u * i + 1u], c = qd_entries[4u * i + 2u], d = qd_entries[4u * i + 3u];
        pixel = ivec2(int(a.x & 0xffffu), int(a.x >> 16));
        g_deferRo = uintBitsToFloat(a.yzw);
        g_deferRd = uintBitsToFloat(b.xyz);
        g_deferTNext = uintBitsToFloat(b.w);
        g_deferThroughput = uintBitsToFloat(c.xyz);
        g_deferCol = vec3(uintBitsToFloat(c.w), uintBitsToFloat(d.xy));
        g_deferPass = true;
    } else
#endif
    pixel.y += u_rowOffset;
    if (pixel.x >= int(u_resolution.x) || pixel.y >= int(u_resolution.y)) return;
#if USE_QUAD_REFLECTIONS
    g_pixel = pixel;
#endif
    vec2 fragCoord = vec2(pixel) + 0.5;
    float tStart = u_conePass == 2 ? imageLoad(u_coneStart, pixel / CONE_TILE).x : 0.0;
    vec4 c = renderPixel(fragCoord, tStart);
#if USE_QUAD_DEFER
    if (g_deferred) return;   // its bounce is in the list: the list's dispatch writes it
#endif
    imageStore(u_output, pixel, c);
}
