/*{
    "DESCRIPTION": "Kaleidoscope: the frame folded into N mirrored wedges around a centre (sdfvj post effect)",
    "CREDIT": "sdfvj",
    "ISFVSN": "2",
    "CATEGORIES": ["Geometry Adjustment"],
    "INPUTS": [
        {"NAME": "inputImage", "TYPE": "image"},
        {"NAME": "sides", "TYPE": "long", "VALUES": [2, 3, 4, 5, 6, 8, 12], "LABELS": ["2", "3", "4", "5", "6", "8", "12"], "DEFAULT": 6, "LABEL": "Mirrors"},
        {"NAME": "rotation", "TYPE": "float", "DEFAULT": 0.0, "MIN": -3.14159, "MAX": 3.14159, "LABEL": "Rotation"},
        {"NAME": "center", "TYPE": "point2D", "DEFAULT": [0.5, 0.5], "MIN": [0.0, 0.0], "MAX": [1.0, 1.0], "LABEL": "Centre (0..1)"}
    ]
}*/
// Kaleidoscope: the angle around `center` is folded into one wedge of 2*pi/sides and mirrored
// inside it, so the picture repeats every 2*pi/sides and is symmetric about each wedge's edge.
// Distances are measured in pixels, so circles stay round on a wide frame.
void main() {
    vec2 px = gl_FragCoord.xy - center * RENDERSIZE;
    float r = length(px);
    float a = atan(px.y, px.x) - rotation;
    float wedge = 6.28318530718 / float(max(sides, 1));
    a = mod(a, wedge);
    a = min(a, wedge - a);
    vec2 q = r * vec2(cos(a + rotation), sin(a + rotation)) + center * RENDERSIZE;
    // out-of-frame samples mirror back in (no clamped smears at the corners)
    vec2 uv = q / RENDERSIZE;
    uv = 1.0 - abs(1.0 - mod(uv, 2.0));
    gl_FragColor = IMG_NORM_PIXEL(inputImage, uv);
}
