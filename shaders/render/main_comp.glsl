// main_comp.glsl - compute-shader entry point (GLSL only): one invocation per pixel in
// 8x8 groups (WORKGROUP_X/Y), dispatch ceil(w/8) x ceil(h/8); writes image unit 0 (rgba8). Row 0 of the
// image is the bottom row, as with the fragment path (fragCoord has the same meaning).
// DEBUG_VIEW 4 and 5 (accuracy bench, NaN scans) write an rgba32f image instead.
//
// The cone pre-pass (render/march.glsl's coneStart; Quality::conePrepass): u_conePass 1 is a dispatch
// of one invocation per 8x8 tile, ceil(w/64) x ceil(h/64) groups, that writes each tile's start
// distance into image unit 1 (r32f, ceil(w/8) x ceil(h/8)); u_conePass 2 is the frame, every
// primary ray starting at its tile's distance; 0 is the frame from the eye, no pre-pass.
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
#if DEBUG_VIEW >= 4
layout(rgba32f, binding = 0) uniform writeonly image2D u_output;
#else
layout(rgba8, binding = 0) uniform writeonly image2D u_output;
#endif
layout(r32f, binding = 1) uniform image2D u_coneStart;
uniform int u_conePass;
uniform int u_rowOffset;   // the frame drawn in strips (FrameRenderer::SetStrips): the strip's first row
const int CONE_TILE = 8;

// CONE_IN_GROUP 1: the cones in the frame's own dispatch, no pre-pass. Each 8x8 tile of a group
// gets its cone from one of the group's first invocations (the tiles' cones in parallel), shared
// through the group's memory: no second dispatch waits for the slowest cone, and a group's cones
// run while other groups shade. (A barrier: llvmpipe runs such a program as coroutines, 73 %
// slower, session 12.) FrameRenderer sees u_coneInGroup and skips the pre-pass.
#ifndef CONE_IN_GROUP
#define CONE_IN_GROUP 0
#endif
#if CONE_IN_GROUP
#if (WORKGROUP_X % 8) != 0 || (WORKGROUP_Y % 8) != 0
#error CONE_IN_GROUP needs a work-group of whole 8x8 tiles
#endif
const int CONE_TILES_X = WORKGROUP_X / CONE_TILE;
const int CONE_TILES_Y = WORKGROUP_Y / CONE_TILE;
shared float s_coneStart[CONE_TILES_X * CONE_TILES_Y];
uniform int u_coneInGroup;
#endif

// Where tile `tile`'s primary rays may start (0 outside the frame, or with the pre-pass compiled out).
float tileStart(ivec2 tile) {
    ivec2 tiles = (ivec2(u_resolution) + CONE_TILE - 1) / CONE_TILE;
    if (tile.x >= tiles.x || tile.y >= tiles.y) return 0.0;
    vec2 lo = vec2(tile * CONE_TILE) + 0.5;
    vec2 hi = min(lo + float(CONE_TILE - 1), u_resolution - 0.5);
#if USE_SUPERSAMPLE
    lo -= 0.5;   // the samples reach the tile's pixels' edges
    hi += 0.5;
#endif
#if CONE_PREPASS
    return coneStart(lo, hi);
#else
    return 0.0;
#endif
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
#if !CONE_IN_GROUP
    if (u_conePass == 1) {
        ivec2 tiles = (ivec2(u_resolution) + CONE_TILE - 1) / CONE_TILE;
        if (pixel.x >= tiles.x || pixel.y >= tiles.y) return;
        imageStore(u_coneStart, pixel, vec4(tileStart(pixel)));
        return;
    }
#endif
    pixel.y += u_rowOffset;
    float tStart = 0.0;
#if CONE_IN_GROUP
    if (u_conePass == 2 && u_coneInGroup != 0) {   // a uniform: every invocation of the group reaches the barrier
        int lid = int(gl_LocalInvocationIndex);
        if (lid < CONE_TILES_X * CONE_TILES_Y) {
            ivec2 first = (ivec2(gl_WorkGroupID.xy) * ivec2(WORKGROUP_X, WORKGROUP_Y) + ivec2(0, u_rowOffset)) / CONE_TILE;
            s_coneStart[lid] = tileStart(first + ivec2(lid % CONE_TILES_X, lid / CONE_TILES_X));
        }
        barrier();
        ivec2 local = ivec2(gl_LocalInvocationID.xy) / CONE_TILE;
        tStart = s_coneStart[local.y * CONE_TILES_X + local.x];
    }
#else
    if (u_conePass == 2) tStart = imageLoad(u_coneStart, pixel / CONE_TILE).x;
#endif
    if (pixel.x >= int(u_resolution.x) || pixel.y >= int(u_resolution.y)) return;
    vec2 fragCoord = vec2(pixel) + 0.5;
    imageStore(u_output, pixel, renderPixel(fragCoord, tStart));
}
