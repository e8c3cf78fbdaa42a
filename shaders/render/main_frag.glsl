// main_frag.glsl - fragment-shader entry point (GLSL only). The host prepends #version,
// the defines, uniforms, scene and render/render.glsl, and draws a full-screen triangle.
out vec4 fragColor;

void main() {
    fragColor = render(gl_FragCoord.xy);
}
