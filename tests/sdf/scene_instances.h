// scene_instances.h - the four scenes compiled as C++ (float and double) with render.glsl
// at its default effect switches, behind one CpuScene struct; plus loading a scene's JSON
// header so inputs, camera, light and material take the values the host would upload.
// Used by the scene tests and by sdf_cpu_preview (a CPU reference render).
#pragma once
#include "sdf/glsl_glm.h"

#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

template <class S>
struct CpuScene {
  using V2 = glm::vec<2, S>;
  using V3 = glm::vec<3, S>;
  using V4 = glm::vec<4, S>;
  std::string name;
  std::function<V4(V3)> map;
  std::function<S()> lipschitz;
  std::function<V4(V2)> render;
  std::map<std::string, S*> inputs;  // u_<name> of every header input
  S* time; int* frame; V2* resolution; S* beat; V3* camPos; V3* camTarget; S* fov;
  V3* lightDir; V3* lightColor; int* maxSteps; S* hitEps; S* maxDist; S* stepFactor;
  S* fixedStep; int* shadowSteps; S* shadowK; int* aoSamples; S* normalEps; S* roughness;
  S* metalness;
};

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

// The JSON object between /* and */ at the top of a scene file.
inline nlohmann::json readSceneHeader(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  auto a = text.find("/*{"), b = text.find("}*/");
  if (a == std::string::npos || b == std::string::npos) throw std::runtime_error(path + ": no JSON header");
  return nlohmann::json::parse(text.substr(a + 2, b - a - 1));
}

// Set every uniform to what the host uploads by default: header inputs, camera, light,
// material, and the default quality (128 steps, eps 1e-3, far 50).
template <class S>
void applyDefaults(CpuScene<S>& s, const nlohmann::json& h, int width, int height) {
  using V3 = typename CpuScene<S>::V3;
  for (auto& in : h["INPUTS"]) {
    auto& d = in["DEFAULT"];
    *s.inputs.at(in["NAME"].get<std::string>()) = d.is_boolean() ? (d.get<bool>() ? S(1) : S(0)) : d.get<S>();
  }
  auto v3 = [](const nlohmann::json& j) { return V3(j[0].get<S>(), j[1].get<S>(), j[2].get<S>()); };
  *s.camPos = v3(h["CAMERA"]["POSITION"]);
  *s.camTarget = v3(h["CAMERA"]["TARGET"]);
  *s.fov = h["CAMERA"]["FOV"].get<S>();
  *s.lightDir = glm::normalize(v3(h["LIGHT"]["DIRECTION"]));
  *s.lightColor = v3(h["LIGHT"]["COLOR"]);
  *s.roughness = h["MATERIAL"]["ROUGHNESS"].get<S>();
  *s.metalness = h["MATERIAL"]["METALNESS"].get<S>();
  *s.time = S(0); *s.frame = 0; *s.beat = S(0);
  *s.resolution = typename CpuScene<S>::V2(S(width), S(height));
  *s.maxSteps = 128; *s.hitEps = S(1e-3); *s.maxDist = S(50); *s.stepFactor = S(1);
  *s.fixedStep = S(0.05); *s.shadowSteps = 64; *s.shadowK = S(12); *s.aoSamples = 5;
  *s.normalEps = S(1e-3);
}
