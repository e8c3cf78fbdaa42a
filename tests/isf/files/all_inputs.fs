/*{
    "DESCRIPTION": "every ISF 2.0 input type; the colour it draws is a function of each",
    "ISFVSN": "2.0",
    "INPUTS": [
        {"NAME": "inputImage", "TYPE": "image"},
        {"NAME": "amount", "TYPE": "float", "DEFAULT": 0.25, "MIN": 0.0, "MAX": 2.0},
        {"NAME": "flag", "TYPE": "bool", "DEFAULT": true},
        {
            "NAME": "choice",
            "TYPE": "long",
            "VALUES": [0, 5, 10],
            "LABELS": ["none", "half", "all"],
            "DEFAULT": 5
        },
        {"NAME": "where", "TYPE": "point2D", "DEFAULT": [10.0, 20.0], "MIN": [0.0, 0.0], "MAX": [100.0, 100.0]},
        {"NAME": "tint", "TYPE": "color", "DEFAULT": [0.25, 0.5, 0.75, 1.0]},
        {"NAME": "bang", "TYPE": "event"},
        {
            "NAME": "wave",
            "TYPE": "audio"
        },
        {"NAME": "spectrum", "TYPE": "audioFFT", "MAX": 16}
    ]
}*/
// Left quarter: amount, flag, choice/10. Second quarter: where/100, bang. Third: tint.
// Right quarter: the input image, plus the audio textures (silent: wave 0.5, spectrum 0).
void main() {
    float x = isf_FragNormCoord.x;
    if (x < 0.25) gl_FragColor = vec4(amount, flag ? 1.0 : 0.0, float(choice) / 10.0, 1.0);
    else if (x < 0.5) gl_FragColor = vec4(where / 100.0, bang ? 1.0 : 0.0, 1.0);
    else if (x < 0.75) gl_FragColor = tint;
    else gl_FragColor = vec4(IMG_THIS_PIXEL(inputImage).r, IMG_NORM_PIXEL(wave, vec2(0.5)).r, IMG_NORM_PIXEL(spectrum, vec2(0.5)).r, 1.0);
}
