/*{
    "DESCRIPTION": "Colour grade: exposure, lift/gamma/gain, saturation, contrast and tint (sdfvj post effect)",
    "CREDIT": "sdfvj",
    "ISFVSN": "2",
    "CATEGORIES": ["Color Adjustment"],
    "INPUTS": [
        {"NAME": "inputImage", "TYPE": "image"},
        {"NAME": "exposure", "TYPE": "float", "DEFAULT": 0.0, "MIN": -4.0, "MAX": 4.0, "LABEL": "Exposure (stops)"},
        {"NAME": "contrast", "TYPE": "float", "DEFAULT": 1.0, "MIN": 0.0, "MAX": 3.0, "LABEL": "Contrast"},
        {"NAME": "saturation", "TYPE": "float", "DEFAULT": 1.0, "MIN": 0.0, "MAX": 3.0, "LABEL": "Saturation"},
        {"NAME": "lift", "TYPE": "color", "DEFAULT": [0.0, 0.0, 0.0, 0.0], "MIN": [-1.0, -1.0, -1.0, 0.0], "MAX": [1.0, 1.0, 1.0, 1.0], "LABEL": "Lift"},
        {"NAME": "gamma", "TYPE": "color", "DEFAULT": [1.0, 1.0, 1.0, 1.0], "MIN": [0.1, 0.1, 0.1, 0.0], "MAX": [4.0, 4.0, 4.0, 1.0], "LABEL": "Gamma"},
        {"NAME": "gain", "TYPE": "color", "DEFAULT": [1.0, 1.0, 1.0, 1.0], "MIN": [0.0, 0.0, 0.0, 0.0], "MAX": [4.0, 4.0, 4.0, 1.0], "LABEL": "Gain"}
    ]
}*/
// Colour grade in the order a colourist applies it: exposure (2^stops), lift/gamma/gain
// (out = (gain * (x + lift * (1 - x)))^(1/gamma)), contrast around mid grey, then saturation
// against Rec. 709 luma. The defaults are the identity.
void main() {
    vec4 src = IMG_THIS_PIXEL(inputImage);
    vec3 c = src.rgb * exp2(exposure);
    c = gain.rgb * (c + lift.rgb * (1.0 - c));
    c = pow(max(c, vec3(0.0)), 1.0 / gamma.rgb);
    c = (c - 0.5) * contrast + 0.5;
    float luma = dot(c, vec3(0.2126, 0.7152, 0.0722));
    c = mix(vec3(luma), c, saturation);
    gl_FragColor = vec4(clamp(c, 0.0, 1.0), src.a);
}
