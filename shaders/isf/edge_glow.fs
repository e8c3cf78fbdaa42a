/*{
    "DESCRIPTION": "Edge glow: Sobel edges of the frame, coloured and added on top (sdfvj post effect)",
    "CREDIT": "sdfvj",
    "ISFVSN": "2",
    "CATEGORIES": ["Stylize"],
    "INPUTS": [
        {"NAME": "inputImage", "TYPE": "image"},
        {"NAME": "strength", "TYPE": "float", "DEFAULT": 1.0, "MIN": 0.0, "MAX": 4.0, "LABEL": "Glow"},
        {"NAME": "glowColor", "TYPE": "color", "DEFAULT": [0.2, 0.8, 1.0, 1.0], "LABEL": "Glow colour"},
        {"NAME": "edgesOnly", "TYPE": "bool", "DEFAULT": false, "LABEL": "Edges only"}
    ]
}*/
// Edge glow: the Sobel gradient of luma (3x3, one-pixel steps) is the edge strength; flat areas
// have none, so they keep their colour exactly; edges add glowColor * strength * |gradient|.
float lumaAt(vec2 px) {
    return dot(IMG_PIXEL(inputImage, px).rgb, vec3(0.2126, 0.7152, 0.0722));
}
void main() {
    vec2 p = gl_FragCoord.xy;
    float tl = lumaAt(p + vec2(-1.0, 1.0)), t = lumaAt(p + vec2(0.0, 1.0)), tr = lumaAt(p + vec2(1.0, 1.0));
    float l = lumaAt(p + vec2(-1.0, 0.0)), r = lumaAt(p + vec2(1.0, 0.0));
    float bl = lumaAt(p + vec2(-1.0, -1.0)), b = lumaAt(p + vec2(0.0, -1.0)), br = lumaAt(p + vec2(1.0, -1.0));
    float gx = (tr + 2.0 * r + br) - (tl + 2.0 * l + bl);
    float gy = (tl + 2.0 * t + tr) - (bl + 2.0 * b + br);
    float edge = clamp(length(vec2(gx, gy)) * 0.25, 0.0, 1.0);
    vec4 src = IMG_THIS_PIXEL(inputImage);
    vec3 base = edgesOnly ? vec3(0.0) : src.rgb;
    gl_FragColor = vec4(clamp(base + glowColor.rgb * edge * strength, 0.0, 1.0), src.a);
}
