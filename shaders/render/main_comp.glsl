// main_comp.glsl - compute-shader entry point (GLSL only): one invocation per pixel in
// 8x8 groups, dispatch ceil(w/8) x ceil(h/8); writes image unit 0 (rgba8). Row 0 of the
// image is the bottom row, as with the fragment path (fragCoord has the same meaning).
// DEBUG_VIEW 4 and 5 (accuracy bench, NaN scans) write an rgba32f image instead.
layout(local_size_x = 8, local_size_y = 8) in;
#if DEBUG_VIEW >= 4
layout(rgba32f, binding = 0) uniform writeonly image2D u_output;
#else
layout(rgba8, binding = 0) uniform writeonly image2D u_output;
#endif

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(u_resolution.x) || pixel.y >= int(u_resolution.y)) return;
    vec2 fragCoord = vec2(gl_GlobalInvocationID.xy) + 0.5;
    imageStore(u_output, pixel, render(fragCoord));
}
