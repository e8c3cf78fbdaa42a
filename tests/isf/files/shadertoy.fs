// A Shadertoy single-pass shader: no ISF header, mainImage, iResolution, iTime, iFrame, iChannel0.
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec2 uv = fragCoord / iResolution.xy;
    vec3 prev = texture(iChannel0, uv).rgb;
    fragColor = vec4(uv.x, iTime / 10.0 + float(iFrame) / 255.0, prev.b, 0.0);
}
