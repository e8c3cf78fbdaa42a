// scene_instances.h - every scene compiled as C++ (float and double) with render.glsl
// at its default effect switches (sdfvj_accuracy's builds), behind one CpuScene struct; plus loading a scene's JSON
// header so inputs, camera, light and material take the values the host would upload.
// Used by the scene tests and by sdf_cpu_preview (a CPU reference render).
#pragma once
#include "accuracy/accuracy.h"
#include "cpu_scene.h"

// Every scene in shaders/scenes (the CPU builds are generated from the folder at configure time).
inline const std::vector<std::string>& sceneNames() {
  static const std::vector<std::string> names = sdfvj::accuracy::CpuSceneNames();
  return names;
}

template <class S> CpuScene<S> makeScene(const std::string& name);
template <> inline CpuScene<float> makeScene<float>(const std::string& name) { return sdfvj::accuracy::MakeCpuScene32(name); }
template <> inline CpuScene<double> makeScene<double>(const std::string& name) { return sdfvj::accuracy::MakeCpuScene64(name); }
