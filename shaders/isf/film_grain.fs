/*{
    "DESCRIPTION": "Film grain: zero-mean noise that changes every frame, stronger in the mid-tones (sdfvj post effect)",
    "CREDIT": "sdfvj",
    "ISFVSN": "2",
    "CATEGORIES": ["Stylize"],
    "INPUTS": [
        {"NAME": "inputImage", "TYPE": "image"},
        {"NAME": "amount", "TYPE": "float", "DEFAULT": 0.08, "MIN": 0.0, "MAX": 0.5, "LABEL": "Grain"},
        {"NAME": "size", "TYPE": "float", "DEFAULT": 1.0, "MIN": 1.0, "MAX": 8.0, "LABEL": "Grain size (pixels)"}
    ]
}*/
// Film grain: a hash of the grain cell and FRAMEINDEX gives uniform noise in [-1, 1] (zero mean,
// standard deviation 1/sqrt(3)); it is scaled by amount and by 4x(1-x) so blacks and whites
// keep their ends. The same frame index gives the same grain (replays are exact).
float grainHash(vec3 p) {
    p = fract(p * vec3(0.1031, 0.1030, 0.0973));
    p += dot(p, p.yxz + 33.33);
    return fract((p.x + p.y) * p.z);
}
void main() {
    vec4 src = IMG_THIS_PIXEL(inputImage);
    vec2 cell = floor(gl_FragCoord.xy / size);
    float n = grainHash(vec3(cell, float(FRAMEINDEX % 4096))) * 2.0 - 1.0;
    float luma = dot(src.rgb, vec3(0.2126, 0.7152, 0.0722));
    float weight = 4.0 * luma * (1.0 - luma);
    gl_FragColor = vec4(clamp(src.rgb + n * amount * weight, 0.0, 1.0), src.a);
}
