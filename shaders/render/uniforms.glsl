// uniforms.glsl - the built-in uniforms of every sdfvj program.
//
// The host includes this BEFORE the scene (so scenes may use u_time, u_beat), then its
// generated `uniform float u_<input>;` lines, then the scene, then render/render.glsl.
// In C++ (src/sdf/glsl_prelude.h) `uniform` is `static`: assign ns::u_time etc. directly.
#ifndef SDF_RENDER_UNIFORMS_GLSL
#define SDF_RENDER_UNIFORMS_GLSL

uniform float u_time;        // seconds since start (replay: frame / fps)
uniform int u_frame;         // frame index
#if !defined(SDF_GLSL_DOUBLE) && !defined(SDF_LOOP_ZERO)
// A 0 the GLSL compiler cannot see, for loops that must stay rolled (lib/common.glsl SDF_LOOP_ZERO).
// C++ builds (src/sdf/glsl_prelude.h defines SDF_GLSL_DOUBLE) get common.glsl's plain 0.
#define SDF_LOOP_ZERO min(u_frame, 0)
#endif
uniform vec2 u_resolution;   // output size in pixels
uniform float u_beat;        // beat phase from the clock / MIDI, 0..1 per beat
uniform float u_bpm;         // tempo: tap, MIDI clock or the preset's "bpm" (120 by default)
uniform vec3 u_camPos;       // camera position
uniform vec3 u_camTarget;    // point the camera looks at
uniform float u_fov;         // vertical field of view, degrees
// The camera's basis, which depends on uniforms only, set by FrameRenderer (MakeCameraBasis) for
// render.glsl's cameraRay() and pixelAngle() (CAMERA_UNIFORMS; the C++ reference computes them):
// ray(fragCoord) = normalize(u_camForward + (fragCoord.x - w/2) u_camDX + (fragCoord.y - h/2) u_camDY),
// u_pixelAngle = 2 tan(fov/2) / h.
#if defined(SDFVJ_COMPUTE) || defined(SDFVJ_FRAGMENT)
uniform vec3 u_camForward;
uniform vec3 u_camDX;
uniform vec3 u_camDY;
uniform float u_pixelAngle;
#endif
uniform vec3 u_lightDir;     // unit direction TOWARDS the directional light
uniform vec3 u_lightColor;   // light colour/intensity (linear)
uniform int u_maxSteps;      // primary-ray march steps (default 128)
uniform float u_hitEps;      // hit threshold at distance 1; scaled by max(1, t)
uniform float u_maxDist;     // far plane (default 50)
uniform float u_stepFactor;  // step multiplier (<= 1 is safe), divided by sceneLipschitz()
uniform float u_fixedStep;   // step length when MARCH_FIXED == 1
uniform int u_shadowSteps;   // shadow-ray steps
uniform float u_shadowK;     // shadow penumbra hardness (8 soft .. 64 hard)
uniform int u_aoSamples;     // ambient occlusion samples
uniform float u_normalEps;   // normal finite-difference step at distance 1; scaled like u_hitEps
uniform float u_roughness;   // material roughness 0..1 (Blinn-Phong exponent or GGX)
uniform float u_metalness;   // material metalness 0..1 (PBR and reflection tint)
// Runtime switches for effects that ARE compiled in: a set bit skips that effect. Only the
// effects benchmark sets it, to show what a uniform branch costs against compiling out.
uniform int u_effectsOff;
const int EFFECT_OFF_SHADOWS = 1;
const int EFFECT_OFF_AO = 2;
const int EFFECT_OFF_SPECULAR = 4;
const int EFFECT_OFF_REFLECTIONS = 8;
const int EFFECT_OFF_FOG = 16;

#endif
