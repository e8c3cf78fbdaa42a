/*{
    "DESCRIPTION": "features sdfvj does not support: each one line, and the file still renders",
    "ISFVSN": "2.0",
    "CATEGORIES": ["test"],
    "VERSION_OF_SOMETHING": "x",
    "INPUTS": [
        {"NAME": "inputImage", "TYPE": "image"},
        {"NAME": "second", "TYPE": "image"},
        {"NAME": "wave", "TYPE": "audio", "MAX": 256},
        {"NAME": "fft", "TYPE": "audioFFT"}
    ],
    "PASSES": [{"DESCRIPTION": "one pass", "BLEND": "add"}]
}*/
void main() {
    gl_FragColor = vec4(IMG_THIS_PIXEL(inputImage).rgb + IMG_THIS_PIXEL(second).rgb * 0.0, 1.0)
                 + vec4(IMG_NORM_PIXEL(wave, vec2(0.5)).r * 0.0, IMG_NORM_PIXEL(fft, vec2(0.5)).r, 0.0, 0.0);
}
