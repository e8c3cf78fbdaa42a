// A Shadertoy mainImage that follows sdfvj's tempo: red is u_beat, green u_bpm / 240.
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    fragColor = vec4(u_beat, u_bpm / 240.0, 0.0, 1.0);
}
