// lib/field.glsl, the grid of blended shapes behind field50 and field150: evaluating the 2x2
// cells around a point gives exactly the field over every shape near the surfaces, a bound
// everywhere else, and stays 1-Lipschitz across cell borders; the scenes' knob ranges stay
// inside what that argument allows, and their bounding spheres hold every shape.
#include <catch2/catch.hpp>

#include <cmath>

#include "reference_geometry.h"
#include "scene_instances.h"

namespace field64 {
namespace {
#define SDF_GLSL_DOUBLE 1
#include "sdf/glsl_prelude.h"
#define float double
#include "lib/field.glsl"
#undef float
#undef SDF_GLSL_DOUBLE
#undef uniform
}  // namespace
}  // namespace field64

namespace {

struct Knobs {
  double size, blend, wave, phase, spin;
};

// Grids of both scenes, at the knob extremes and in between.
std::vector<Knobs> knobCases() {
  std::vector<Knobs> out;
  for (double size : {0.3, 0.7, field64::FIELD_MAX_SIZE})
    for (double blend : {0.0, 0.15, field64::FIELD_MAX_BLEND})
      for (double wave : {0.0, 1.5}) out.push_back({size, blend, wave, 1.7 + size, 0.9 * wave});
  return out;
}

}  // namespace

TEST_CASE("sdf field: the 2x2 evaluation equals the all-shapes field near surfaces and bounds it elsewhere", "[sdf][field]") {
  for (auto [nx, nz] : {std::pair{10.0, 5.0}, std::pair{15.0, 10.0}, std::pair{2.0, 3.0}}) {
    for (const Knobs& k : knobCases()) {
      ref::Sampler s;
      int near = 0, exactNear = 0, above = 0, nonPositiveMismatch = 0;
      double worstExcess = -1e9;
      for (int i = 0; i < 6000; ++i) {
        // over the grid and a margin around it, from below the floor to above the wave; every
        // other sample close to a random cell's shape
        glm::dvec3 p(s.range(-0.5 * nx - 1.5, 0.5 * nx + 1.5), s.range(-0.2, 2.8), s.range(-0.5 * nz - 1.5, 0.5 * nz + 1.5));
        if (i % 2) {
          double ci = std::floor(s.range(0.0, nx)), cj = std::floor(s.range(0.0, nz));
          p = glm::dvec3(ci - 0.5 * (nx - 1.0) + s.range(-0.6, 0.6), s.range(-0.05, field64::fieldTop(k.size, k.wave) + 0.1),
                         cj - 0.5 * (nz - 1.0) + s.range(-0.6, 0.6));
        }
        double f = field64::fieldMap(p, nx, nz, k.size, k.blend, k.wave, k.phase, k.spin).w;
        double F = field64::fieldMapAll(p, nx, nz, k.size, k.blend, k.wave, k.phase, k.spin).w;
        worstExcess = std::max(worstExcess, f - F);
        if ((f > 0) != (F > 0)) ++nonPositiveMismatch;
        // within 0.1 of the surface (the argument guarantees 1 - 0.385 - 1.25 * 0.35 = 0.18)
        if (F < 0.1) {
          ++near;
          if (std::abs(f - F) < 1e-12) ++exactNear;
        } else {
          ++above;
        }
      }
      INFO(nx << "x" << nz << " size " << k.size << " blend " << k.blend << " wave " << k.wave << ": " << near
                << " samples near surfaces, " << exactNear << " exact; worst f - F " << worstExcess);
      CHECK(worstExcess <= 1e-12);        // never above the true field: a safe step
      CHECK(exactNear == near);           // the surface, its normals and close probes are the field's own
      CHECK(nonPositiveMismatch == 0);    // same inside/outside everywhere
      CHECK(near > 20);                   // the test sampled surfaces at all
      CHECK(above > 50);
    }
  }
}

TEST_CASE("sdf field: 1-Lipschitz across cell borders at every knob extreme", "[sdf][field]") {
  for (const Knobs& k : knobCases()) {
    ref::Sampler s;
    double worst = 0;
    for (int i = 0; i < 20000; ++i) {
      glm::dvec3 a(s.range(-9.0, 9.0), s.range(-0.2, 3.0), s.range(-6.5, 6.5));
      // short steps across borders (cell size 1) as well as long ones
      glm::dvec3 b = a + s.direction() * s.range(1e-4, 0.6);
      double fa = field64::fieldMap(a, 15.0, 10.0, k.size, k.blend, k.wave, k.phase, k.spin).w;
      double fb = field64::fieldMap(b, 15.0, 10.0, k.size, k.blend, k.wave, k.phase, k.spin).w;
      worst = std::max(worst, std::abs(fa - fb) / glm::length(a - b));
    }
    INFO("size " << k.size << " blend " << k.blend << " wave " << k.wave << ": worst slope " << worst);
    CHECK(worst <= 1.0 + 1e-9);
  }
}

TEST_CASE("sdf field: every shape lies inside the radius and height the cut-off assumes", "[sdf][field]") {
  // Sample each cell's shape on a fine lattice: no inside point beyond FIELD_RADIUS * size of
  // its axis, above fieldTop or below the floor.
  for (const Knobs& k : knobCases()) {
    double worstR = 0, worstTop = -1e9, lowest = 1e9;
    for (double ci = 0; ci < 6; ++ci)
      for (double cj = 0; cj < 4; ++cj)
        for (double x = -0.5; x <= 0.5; x += 0.02)
          for (double z = -0.5; z <= 0.5; z += 0.02)
            for (double y = -0.1; y <= 2.8; y += 0.02) {
              glm::dvec3 q(x, y, z);
              if (field64::fieldShape(q, ci, cj, k.size, k.wave, k.phase, k.spin) > 0) continue;
              worstR = std::max(worstR, std::hypot(x, z) / k.size);
              worstTop = std::max(worstTop, y - field64::fieldTop(k.size, k.wave));
              lowest = std::min(lowest, y);
            }
    INFO("size " << k.size << " wave " << k.wave);
    CHECK(worstR <= field64::FIELD_RADIUS);
    CHECK(worstTop <= 0.0);
    CHECK(lowest >= -1e-9);
  }
  // the argument's margin is positive at the largest knobs
  CHECK(1.0 - field64::FIELD_RADIUS * field64::FIELD_MAX_SIZE - 1.25 * field64::FIELD_MAX_BLEND > 0.1);
}

TEST_CASE("sdf field: field50 and field150 keep their knobs inside the field's limits and their bound holds the shapes", "[sdf][field]") {
  for (const char* name : {"field50", "field150"}) {
    sdfvj::SceneInfo info;
    std::string error;
    REQUIRE(sdfvj::FindScene(name, &info, &error));
    for (const auto& p : info.params) {
      INFO(name << " " << p.name);
      if (p.name == "blend") CHECK(p.maxValue <= field64::FIELD_MAX_BLEND);
      if (p.name == "size") CHECK(p.maxValue <= field64::FIELD_MAX_SIZE);
      if (p.name == "wave") CHECK(p.minValue >= 0.0f);
    }
    auto sc = sdfvj::accuracy::MakeCpuScene64(name);
    REQUIRE(sc.hasBound);
    sdfvj::FrameInputs in;
    in.time = 2.0;
    for (const auto& p : info.params) in.params.emplace_back(p.name, p.maxValue);   // largest shapes, highest wave
    sdfvj::accuracy::ApplyFrame(sc, info, in, 64, 36);
    glm::dvec4 b = sc.sceneBound();
    // every surface point of the shapes (map < 0 off the floor) inside the sphere
    ref::Sampler s;
    int inside = 0;
    for (int i = 0; i < 200000; ++i) {
      glm::dvec3 p = glm::dvec3(b.x, b.y, b.z) + s.point(b.w);
      if (p.y < 0.1 || sc.map(p).w > 0) continue;
      ++inside;
      CHECK(glm::length(p - glm::dvec3(b.x, b.y, b.z)) < b.w);
    }
    CHECK(inside > 100);
  }
}
