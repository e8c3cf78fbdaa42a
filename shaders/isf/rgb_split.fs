/*{
    "DESCRIPTION": "RGB split: red and blue channels shifted apart along a direction (sdfvj post effect)",
    "CREDIT": "sdfvj",
    "ISFVSN": "2",
    "CATEGORIES": ["Stylize"],
    "INPUTS": [
        {"NAME": "inputImage", "TYPE": "image"},
        {"NAME": "amount", "TYPE": "float", "DEFAULT": 4.0, "MIN": 0.0, "MAX": 64.0, "LABEL": "Shift (pixels)"},
        {"NAME": "angle", "TYPE": "float", "DEFAULT": 0.0, "MIN": -3.14159, "MAX": 3.14159, "LABEL": "Direction"}
    ]
}*/
// RGB split: red is sampled `amount` pixels ahead along `angle`, blue the same distance behind,
// green in place. So a white line at x shows red at x - amount and blue at x + amount.
void main() {
    vec2 px = gl_FragCoord.xy;
    vec2 d = amount * vec2(cos(angle), sin(angle));
    vec4 g = IMG_PIXEL(inputImage, px);
    float r = IMG_PIXEL(inputImage, px + d).r;
    float b = IMG_PIXEL(inputImage, px - d).b;
    gl_FragColor = vec4(r, g.g, b, g.a);
}
