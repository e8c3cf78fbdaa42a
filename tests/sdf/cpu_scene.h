// cpu_scene.h - CpuScene: one scene + render.glsl compiled as C++ (see scene_instance.inc),
// reached through pointers to its uniforms; plus reading a scene's JSON header and setting
// the uniforms the host would upload by default.
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
