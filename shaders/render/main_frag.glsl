// main_frag.glsl - fragment-shader entry point (GLSL only). The host prepends #version,
// the defines, uniforms, scene, render/render.glsl and render/supersample.glsl, and draws a
// full-screen triangle.
out vec4 fragColor;

void main() {
    fragColor = renderPixel(gl_FragCoord.xy, 0.0);
}
