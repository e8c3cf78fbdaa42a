/*{
  "ISFVSN": "2",
  "DESCRIPTION": "Test generator: the audioFFT input in red, the audio wave in green, one column per bin/sample.",
  "CATEGORIES": ["Test"],
  "INPUTS": [
    {"NAME": "wave", "TYPE": "audio"},
    {"NAME": "fft", "TYPE": "audioFFT"}
  ]
}*/
void main() {
    vec2 uv = isf_FragNormCoord;
    float s = IMG_NORM_PIXEL(fft, vec2(uv.x, 0.5)).r;
    float w = IMG_NORM_PIXEL(wave, vec2(uv.x, 0.5)).r;
    gl_FragColor = vec4(s, w, 0.0, 1.0);
}
