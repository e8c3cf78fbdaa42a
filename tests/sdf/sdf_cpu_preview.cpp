// sdf_cpu_preview - render a scene on the CPU through the very render.glsl the GPU runs
// (default effect switches: soft shadows, AO, Blinn-Phong, fog), to a binary PPM.
// Usage: sdf_cpu_preview SCENE WIDTH HEIGHT TIME OUT.ppm [--double] [name=value ...]
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "scene_instances.h"

template <class S>
int run(const std::string& name, int w, int h, double t, const char* out, int argc, char** argv, int firstKnob) {
  auto sc = makeScene<S>(name);
  applyDefaults(sc, readSceneHeader(std::string(SDFVJ_SHADERS_DIR) + "/scenes/" + name + ".glsl"), w, h);
  *sc.time = S(t);
  for (int i = firstKnob; i < argc; ++i) {
    std::string a = argv[i];
    auto eq = a.find('=');
    if (eq != std::string::npos) *sc.inputs.at(a.substr(0, eq)) = S(std::atof(a.c_str() + eq + 1));
  }
  std::vector<unsigned char> img(size_t(w) * h * 3);
  std::vector<std::thread> pool;
  unsigned n = std::max(1u, std::thread::hardware_concurrency());
  for (unsigned k = 0; k < n; ++k)
    pool.emplace_back([&, k] {
      for (int y = int(k); y < h; y += int(n))
        for (int x = 0; x < w; ++x) {
          auto c = sc.render(typename CpuScene<S>::V2(x + 0.5, y + 0.5));
          size_t o = (size_t(h - 1 - y) * w + x) * 3;  // PPM rows go top-down
          for (int j = 0; j < 3; ++j) img[o + j] = (unsigned char)std::clamp(int(c[j] * 255.0 + 0.5), 0, 255);
        }
    });
  for (auto& th : pool) th.join();
  FILE* f = std::fopen(out, "wb");
  if (!f) return 1;
  std::fprintf(f, "P6\n%d %d\n255\n", w, h);
  std::fwrite(img.data(), 1, img.size(), f);
  std::fclose(f);
  return 0;
}

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: %s SCENE WIDTH HEIGHT TIME OUT.ppm [--double] [name=value ...]\n", argv[0]);
    return 2;
  }
  bool dbl = argc > 6 && std::string(argv[6]) == "--double";
  int w = std::atoi(argv[2]), h = std::atoi(argv[3]);
  double t = std::atof(argv[4]);
  return dbl ? run<double>(argv[1], w, h, t, argv[5], argc, argv, 7)
             : run<float>(argv[1], w, h, t, argv[5], argc, argv, 6);
}
