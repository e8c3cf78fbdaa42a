// The scenes compiled as C++ (float and double) through the same files the GPU uses:
// headers are valid, maps are finite at every knob extreme, sceneLipschitz() really bounds
// the gradient, float and double agree, and render() gives finite display colours.
#include <catch2/catch.hpp>

#include "reference_geometry.h"
#include "scene_instances.h"

namespace {
std::string scenePath(const std::string& name) { return std::string(SDFVJ_SHADERS_DIR) + "/scenes/" + name + ".glsl"; }

// Knob settings worth testing: defaults, all minima, all maxima, and random mixes.
std::vector<std::map<std::string, double>> knobSettings(const nlohmann::json& h, int randomCount) {
  std::vector<std::map<std::string, double>> out(3 + randomCount);
  ref::Sampler s;
  for (auto& in : h["INPUTS"]) {
    std::string n = in["NAME"];
    auto& d = in["DEFAULT"];
    double def = d.is_boolean() ? (d.get<bool>() ? 1.0 : 0.0) : d.get<double>();
    double lo = in.contains("MIN") ? in["MIN"].get<double>() : 0.0;
    double hi = in.contains("MAX") ? in["MAX"].get<double>() : 1.0;
    out[0][n] = def;
    out[1][n] = lo;
    out[2][n] = hi;
    for (int i = 0; i < randomCount; ++i) out[3 + i][n] = s.range(lo, hi);
  }
  return out;
}
}  // namespace

TEST_CASE("sdf scenes: the CPU builds are exactly the scenes in shaders/scenes", "[sdf][scene]") {
  // Generated at configure time from the folder: a scene file added without a CPU build (or a
  // build left behind by a removed file) would leave the accuracy report silently incomplete.
  CHECK(sdfvj::accuracy::CpuSceneNames() == sdfvj::ListScenes());
  REQUIRE(!sdfvj::accuracy::CpuSceneNames().empty());
  for (const auto& name : sdfvj::ListScenes()) {
    INFO(name);
    CHECK(sdfvj::accuracy::HasCpuScene(name));
    CHECK(sdfvj::accuracy::MakeCpuScene64(name).name == name);
    // every header input reaches a uniform of the CPU build
    sdfvj::SceneInfo info;
    std::string error;
    REQUIRE(sdfvj::FindScene(name, &info, &error));
    auto s = sdfvj::accuracy::MakeCpuScene32(name);
    CHECK(s.inputs.size() == info.params.size());
    for (const auto& p : info.params) CHECK(s.inputs.count(p.name) == 1);
  }
  // midi reads SCENE_GLOBAL_LIPSCHITZ (its raw field for the plain row), character does not
  CHECK(sdfvj::accuracy::HasGlobalLipschitzBuild("midi"));
  CHECK_FALSE(sdfvj::accuracy::HasGlobalLipschitzBuild("character"));
  CHECK(sdfvj::accuracy::MakeCpuSceneGlobal32("midi").name == "midi");
}

TEST_CASE("sdf scenes: JSON headers have the agreed shape", "[sdf][scene]") {
  for (auto& name : sceneNames()) {
    INFO(name);
    auto h = readSceneHeader(scenePath(name));
    CHECK(h["NAME"] == name);
    CHECK(h["DESCRIPTION"].is_string());
    std::ifstream in(scenePath(name));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (auto& i : h["INPUTS"]) {
      std::string n = i["NAME"], type = i["TYPE"];
      INFO("input " << n);
      CHECK((type == "float" || type == "int" || type == "bool"));
      CHECK(i["LABEL"].is_string());
      CHECK(text.find("u_" + n) != std::string::npos);                      // used by the scene
      CHECK(text.find("uniform float u_" + n) == std::string::npos);        // but not declared
      if (type != "bool") {
        CHECK(i["MIN"].get<double>() <= i["DEFAULT"].get<double>());
        CHECK(i["DEFAULT"].get<double>() <= i["MAX"].get<double>());
      }
    }
    auto& e = h["EFFECTS"];
    std::string shadows = e["SHADOWS"];
    CHECK((shadows == "none" || shadows == "hard" || shadows == "soft" || shadows == "improved"));
    for (auto key : {"AO", "SPECULAR", "PBR", "FOG"}) CHECK(e[key].is_boolean());
    CHECK(e["REFLECTIONS"].is_number_integer());
    CHECK(h["CAMERA"]["POSITION"].size() == 3);
    CHECK(h["CAMERA"]["TARGET"].size() == 3);
    CHECK(h["CAMERA"]["FOV"].is_number());
    CHECK(h["LIGHT"]["DIRECTION"].size() == 3);
    CHECK(h["LIGHT"]["COLOR"].size() == 3);
    CHECK(h["MATERIAL"]["ROUGHNESS"].is_number());
    CHECK(h["MATERIAL"]["METALNESS"].is_number());
  }
}

TEST_CASE("sdf scenes: map is finite and sceneLipschitz bounds its gradient at every knob extreme", "[sdf][scene]") {
  for (auto& name : sceneNames()) {
    auto h = readSceneHeader(scenePath(name));
    auto sc = makeScene<double>(name);
    applyDefaults(sc, h, 160, 120);
    glm::dvec3 centre = glm::dvec3(sc.camTarget->x, sc.camTarget->y, sc.camTarget->z);
    int setting = 0;
    for (auto& knobs : knobSettings(h, 6)) {
      for (auto& [k, v] : knobs) *sc.inputs.at(k) = v;
      for (double t : {0.0, 1.3, 7.7}) {
        *sc.time = t;
        *sc.beat = std::fmod(t, 1.0);
        double L = sc.lipschitz();
        INFO(name << " knob setting " << setting << " t=" << t << " claimed L=" << L);
        REQUIRE(std::isfinite(L));
        REQUIRE(L >= 1.0);
        ref::Sampler s;
        double worst = 0;
        for (int i = 0; i < 4000; ++i) {
          glm::dvec3 a = centre + s.point(3.0);
          glm::dvec3 b = a + s.direction() * s.range(1e-3, 0.1);
          glm::dvec4 ma = sc.map(a), mb = sc.map(b);
          REQUIRE(std::isfinite(ma.w));
          REQUIRE(std::isfinite(ma.x + ma.y + ma.z));
          worst = std::max(worst, std::abs(ma.w - mb.w) / glm::length(a - b));
        }
        // the Mandelbulb's estimator is not Lipschitz near the set; only finiteness there
        if (name != "mandelbulb") CHECK(worst <= L * 1.0001);
        // far away and at the origin the field is finite too
        CHECK(std::isfinite(sc.map(glm::dvec3(0.0)).w));
        CHECK(std::isfinite(sc.map(glm::dvec3(1e4, 3e3, -2e4)).w));
      }
      ++setting;
    }
  }
}

TEST_CASE("sdf scenes: float and double builds agree", "[sdf][scene]") {
  for (auto& name : sceneNames()) {
    auto h = readSceneHeader(scenePath(name));
    auto s32 = makeScene<float>(name);
    auto s64 = makeScene<double>(name);
    applyDefaults(s32, h, 160, 120);
    applyDefaults(s64, h, 160, 120);
    *s32.time = 2.5f;
    *s64.time = 2.5;
    ref::Sampler s;
    double worst = 0;
    for (int i = 0; i < 2000; ++i) {
      glm::dvec3 p = glm::dvec3(s64.camTarget->x, s64.camTarget->y, s64.camTarget->z) + s.point(2.5);
      worst = std::max(worst, std::abs(double(s32.map(glm::vec3(p)).w) - s64.map(p).w));
    }
    INFO(name << ": worst |map32 - map64| = " << worst);
    CHECK(worst < (name == "mandelbulb" ? 1e-3 : 1e-4));
  }
}

TEST_CASE("sdf scenes: render() gives finite display colours and sees the scene", "[sdf][scene]") {
  for (auto& name : sceneNames()) {
    auto h = readSceneHeader(scenePath(name));
    auto sc = makeScene<float>(name);
    const int w = 32, hgt = 24;
    applyDefaults(sc, h, w, hgt);
    *sc.time = 1.0f;
    int distinct = 0;
    glm::vec4 first = sc.render(glm::vec2(0.5f));
    for (int y = 0; y < hgt; ++y)
      for (int x = 0; x < w; ++x) {
        glm::vec4 c = sc.render(glm::vec2(x + 0.5f, y + 0.5f));
        INFO(name << " pixel " << x << "," << y);
        REQUIRE(std::isfinite(c.x + c.y + c.z + c.w));
        CHECK(c.w == 1.0f);
        CHECK(glm::all(glm::greaterThanEqual(glm::vec3(c), glm::vec3(-0.01f))));
        CHECK(glm::all(glm::lessThanEqual(glm::vec3(c), glm::vec3(1.01f))));
        if (glm::length(glm::vec3(c - first)) > 0.05f) ++distinct;
      }
    INFO(name);
    CHECK(distinct > w * hgt / 10);  // not a flat image
  }
}
