// cpu_scene.h - CpuScene (sdfvj_accuracy's: one scene + render.glsl compiled as C++, reached
// through pointers to its uniforms), plus reading a scene's JSON header and setting the
// uniforms the host would upload by default.
#pragma once
#include "accuracy/cpu_scene.h"
#include "sdf/glsl_glm.h"

#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

// The scene instances are sdfvj_accuracy's (src/accuracy/scene_instance.inc), one per scene
// and precision; these tests reach them through the same struct.
using sdfvj::accuracy::CpuScene;

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
