// Helpers of the stability suite: parameter points over a scene's declared range, float-target
// GPU renders (DEBUG_VIEW 4 geometry, 5 linear radiance), the suite's own CPU scenes.
#pragma once
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "accuracy/accuracy.h"

namespace stability {

using Params = std::vector<std::pair<std::string, float>>;
sdfvj::accuracy::CpuScene<float> Hard32();
sdfvj::accuracy::CpuScene<double> Hard64();
sdfvj::accuracy::CpuScene<float> Bulb32();
sdfvj::accuracy::CpuScene<double> Bulb64();

inline std::string TestScene(const std::string& file) { return std::string(SDFVJ_STABILITY_SCENES) + "/" + file; }

// Every corner of the parameter box, then `randomCount` uniform points (deterministic).
inline std::vector<Params> ParamPoints(const sdfvj::SceneInfo& scene, int randomCount, unsigned seed = 7) {
    std::vector<Params> out;
    const size_t n = scene.params.size();
    for (size_t mask = 0; mask < (size_t(1) << n); ++mask) {
        Params p;
        for (size_t i = 0; i < n; ++i) {
            const auto& d = scene.params[i];
            p.emplace_back(d.name, (mask >> i) & 1 ? d.maxValue : d.minValue);
        }
        out.push_back(p);
    }
    std::mt19937 rng(seed);
    for (int r = 0; r < randomCount; ++r) {
        Params p;
        for (const auto& d : scene.params)
            p.emplace_back(d.name, std::uniform_real_distribution<float>(d.minValue, d.maxValue)(rng));
        out.push_back(p);
    }
    return out;
}

inline std::string Describe(const Params& p) {
    std::string s;
    for (const auto& [n, v] : p) s += n + "=" + std::to_string(v) + " ";
    return s;
}

// One program drawn into a float target.
struct FloatRender {
    std::unique_ptr<sdfvj::Program> program = std::make_unique<sdfvj::Program>();
    sdfvj::FrameRenderer fr;
    bool Build(const sdfvj::SceneInfo& scene, sdfvj::EffectSet e, sdfvj::RenderPath path, int debugView, int w, int h,
               std::string* error, const std::vector<std::string>& defines = {}) {
        e.debugView = debugView;
        return sdfvj::accuracy::BuildProgram(scene, e, path, defines, program.get(), error) && fr.Resize(w, h, error, true);
    }
    std::vector<float> Draw(const sdfvj::SceneInfo& scene, const sdfvj::FrameInputs& in) {
        fr.Draw(*program, scene, in);
        return fr.ReadPixelsFloat();
    }
};

}  // namespace stability
