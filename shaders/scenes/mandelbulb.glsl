/*{
  "NAME": "mandelbulb", "DESCRIPTION": "The power-n Mandelbulb fractal, coloured by its orbit trap, inside a bounding sphere.",
  "INPUTS": [
    {"NAME": "power", "TYPE": "float", "DEFAULT": 8.0, "MIN": 2.0, "MAX": 12.0, "LABEL": "Power"},
    {"NAME": "iterations", "TYPE": "int", "DEFAULT": 8, "MIN": 1, "MAX": 16, "LABEL": "Iterations"},
    {"NAME": "hue", "TYPE": "float", "DEFAULT": 0.5, "MIN": 0.0, "MAX": 1.0, "LABEL": "Hue"},
    {"NAME": "colorSpread", "TYPE": "float", "DEFAULT": 0.8, "MIN": 0.0, "MAX": 3.0, "LABEL": "Colour spread"},
    {"NAME": "spin", "TYPE": "float", "DEFAULT": 0.15, "MIN": 0.0, "MAX": 1.0, "LABEL": "Spin speed"}
  ],
  "EFFECTS": {"SHADOWS": "soft", "AO": true, "SPECULAR": true, "PBR": false, "REFLECTIONS": 0, "FOG": true},
  "CAMERA": {"POSITION": [0, 1.3, -2.9], "TARGET": [0, 0, 0], "FOV": 45},
  "LIGHT": {"DIRECTION": [0.55, 0.75, -0.35], "COLOR": [1, 0.95, 0.88]},
  "MATERIAL": {"ROUGHNESS": 0.45, "METALNESS": 0.0}
}*/
// mandelbulb.glsl - the Mandelbulb (lib/mandelbulb.glsl) spinning around Y; u_power is
// the exponent, u_iterations the iteration count (an int input, uploaded as float),
// u_hue/u_colorSpread map the orbit trap to a cosine palette.
#include "lib/common.glsl"
#include "lib/domain.glsl"
#include "lib/mandelbulb.glsl"

vec3 bulbPalette(float trap) {
    float t = u_hue + u_colorSpread * trap;
    vec3 c = 0.5f + 0.5f * cos(TAU * (vec3(t) + vec3(0.0f, 0.12f, 0.25f)));
    // deep orbits (small trap) are crevices: darken them like cheap occlusion
    return c * c * (0.2f + 0.8f * saturate(trap * 2.0f));
}

// What every map() call of a pixel shares, computed once per invocation (render.glsl SCENE_SETUP):
// the spin's cos/sin and the bounding radius (a pow).
SCENE_STATE vec2 g_spin;
SCENE_STATE float g_boundR;
void sceneSetup() {
    float a = u_time * u_spin;
    g_spin = vec2(cos(a), sin(a));
    g_boundR = mandelbulbBoundingRadius(max(u_power, 2.0f));
}
#define SCENE_SETUP 1

vec4 map(vec3 p) {
    vec3 q = vec3(g_spin.x * p.x - g_spin.y * p.z, p.y, g_spin.y * p.x + g_spin.x * p.z);   // pRotateY(p, u_time * u_spin)
    int iterations = int(clamp(u_iterations, 1.0f, 32.0f) + 0.5f);
    vec2 dt = fMandelbulbTrapBounded(q, u_power, iterations, g_boundR);
    return vec4(bulbPalette(dt.y), dt.x);
}

// Bounding volume for the renderer (render.glsl BOUNDS): the bulb's own bounding sphere (seed
// 001) plus the margin inside which fMandelbulbTrap switches to the estimator. No ground.
#define SCENE_BOUND 1
vec4 sceneBound() { return vec4(0.0f, 0.0f, 0.0f, mandelbulbBoundingRadius(max(u_power, 2.0f)) + 0.1f); }

// With `quad_reflections`, the fractal's folds leave many pixels no quad lends its bounce to: they
// are listed and traced in a dispatch of their own (quad_reflections.glsl QUAD_REFLECTIONS_DEFER), 5 % off its
// 7680x4320 show on an H200 (9.10 -> 8.63 ms). Scenes with few such pixels pay more for the list's
// dispatch than they save (docs/performance.md, session 48). Guarded, so a copy can try without.
#ifndef QUAD_REFLECTIONS_DEFER
#define QUAD_REFLECTIONS_DEFER 1
#endif
// The quads lend their centres' AO, not their shadows (quad_reflections.glsl QUAD_SHADE): the folds'
// self-shadowing changes faster than two pixels, so few pixels borrow a shadow and the quads' own
// shadow rays cost more than they save. H100, 7680x4320 show: 8.777 ms lending nothing, 8.701 the
// AO, 8.760 both (docs/performance.md, session 50).
#ifndef QUAD_SHADE
#define QUAD_SHADE 1
#endif

// The distance estimate overshoots a little close to the surface.
float sceneLipschitz() { return 1.1f; }
