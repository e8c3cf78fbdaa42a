// scene_instances.h - the four scenes compiled as C++ (float and double) with render.glsl
// at its default effect switches, behind one CpuScene struct; plus loading a scene's JSON
// header so inputs, camera, light and material take the values the host would upload.
// Used by the scene tests and by sdf_cpu_preview (a CPU reference render).
#pragma once
#include "cpu_scene.h"

#define PRIMITIVES_INPUTS(X) X(smoothness) X(spin) X(bob) X(checker)
#define MIDI_INPUTS(X) X(scale) X(twist) X(displacement) X(smoothness) X(spin)
#define CHARACTER_INPUTS(X) X(speed) X(wave) X(blend) X(floorBlend)
#define MANDELBULB_INPUTS(X) X(power) X(iterations) X(hue) X(colorSpread) X(spin)

#define SCENE_FILE "scenes/primitives.glsl"
#define SCENE_INPUTS PRIMITIVES_INPUTS
#define SCENE_DOUBLE 0
#define SCENE_NS primitives32
#include "scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS primitives64
#include "scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#undef SCENE_INPUTS
#undef SCENE_FILE

#define SCENE_FILE "scenes/midi.glsl"
#define SCENE_INPUTS MIDI_INPUTS
#define SCENE_DOUBLE 0
#define SCENE_NS midi32
#include "scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS midi64
#include "scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#undef SCENE_INPUTS
#undef SCENE_FILE

#define SCENE_FILE "scenes/character.glsl"
#define SCENE_INPUTS CHARACTER_INPUTS
#define SCENE_DOUBLE 0
#define SCENE_NS character32
#include "scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS character64
#include "scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#undef SCENE_INPUTS
#undef SCENE_FILE

#define SCENE_FILE "scenes/mandelbulb.glsl"
#define SCENE_INPUTS MANDELBULB_INPUTS
#define SCENE_DOUBLE 0
#define SCENE_NS mandelbulb32
#include "scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#define SCENE_DOUBLE 1
#define SCENE_NS mandelbulb64
#include "scene_instance.inc"
#undef SCENE_NS
#undef SCENE_DOUBLE
#undef SCENE_INPUTS
#undef SCENE_FILE

inline const std::vector<std::string>& sceneNames() {
  static const std::vector<std::string> names = {"primitives", "midi", "character", "mandelbulb"};
  return names;
}

template <class S> CpuScene<S> makeScene(const std::string& name);
template <> inline CpuScene<float> makeScene<float>(const std::string& name) {
  CpuScene<float> s = name == "primitives" ? primitives32::instance()
                    : name == "midi"       ? midi32::instance()
                    : name == "character"  ? character32::instance()
                    : name == "mandelbulb" ? mandelbulb32::instance()
                    : throw std::runtime_error("unknown scene " + name);
  s.name = name;
  return s;
}
template <> inline CpuScene<double> makeScene<double>(const std::string& name) {
  CpuScene<double> s = name == "primitives" ? primitives64::instance()
                     : name == "midi"       ? midi64::instance()
                     : name == "character"  ? character64::instance()
                     : name == "mandelbulb" ? mandelbulb64::instance()
                     : throw std::runtime_error("unknown scene " + name);
  s.name = name;
  return s;
}

