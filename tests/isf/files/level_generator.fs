/*{
  "ISFVSN": "2",
  "DESCRIPTION": "Test generator: red is level / 2 (level: MIN 0, MAX 2), green is the spectrum's mean.",
  "CATEGORIES": ["Test"],
  "INPUTS": [
    {"NAME": "level", "TYPE": "float", "DEFAULT": 0.5, "MIN": 0.0, "MAX": 2.0},
    {"NAME": "gain", "TYPE": "float", "MAX": 4.0},
    {"NAME": "fft", "TYPE": "audioFFT", "MAX": 8}
  ]
}*/
void main() {
    float s = 0.0;
    for (int i = 0; i < 8; ++i) s += IMG_PIXEL(fft, vec2(float(i) + 0.5, 0.5)).r / 8.0;
    gl_FragColor = vec4(level / 2.0, s, gain / 4.0, 1.0);
}
