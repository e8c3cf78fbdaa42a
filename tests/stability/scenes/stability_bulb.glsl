/*{
  "NAME": "stability_bulb", "DESCRIPTION": "Test scene of the stability suite: the Mandelbulb over powers 1..16 and 1..16 iterations.",
  "INPUTS": [
    {"NAME": "power", "TYPE": "float", "DEFAULT": 8.0, "MIN": 1.0, "MAX": 16.0, "LABEL": "Power"},
    {"NAME": "iterations", "TYPE": "int", "DEFAULT": 8, "MIN": 1, "MAX": 16, "LABEL": "Iterations"}
  ],
  "EFFECTS": {"SHADOWS": "soft", "AO": true, "SPECULAR": true, "PBR": false, "REFLECTIONS": 0, "FOG": true},
  "CAMERA": {"POSITION": [0, 1.3, -2.9], "TARGET": [0, 0, 0], "FOV": 45},
  "LIGHT": {"DIRECTION": [0.55, 0.75, -0.35], "COLOR": [1, 0.95, 0.88]},
  "MATERIAL": {"ROUGHNESS": 0.45, "METALNESS": 0.0}
}*/
// stability_bulb.glsl - lib/mandelbulb.glsl with the power range widened to 1..16.
#include "lib/common.glsl"
#include "lib/mandelbulb.glsl"

vec4 map(vec3 p) {
    int iterations = int(clamp(u_iterations, 1.0f, 32.0f) + 0.5f);
    vec2 dt = fMandelbulbTrap(p, u_power, iterations);
    return vec4(vec3(0.3f + 0.6f * dt.y), dt.x);
}

float sceneLipschitz() { return 1.1f; }
