// Primitive tests of the shared GLSL SDF library, in float (sdf32) and double (sdf64).
#include <catch2/catch.hpp>

#include <functional>
#include <vector>

#include "reference_geometry.h"
#include "sdf/sdf32.h"
#include "sdf/sdf64.h"

#define NS sdf32
#define PREC "float"
#define TOL 2e-5
#define CASES_NS cases32
#include "lib_cases.inc"
#undef NS
#undef PREC
#undef TOL
#undef CASES_NS

#define NS sdf64
#define PREC "double"
#define TOL 1e-9
#define CASES_NS cases64
#include "lib_cases.inc"
#undef NS
#undef PREC
#undef TOL
#undef CASES_NS

// The Mandelbulb's whole-power step (complex squaring, no trigonometry) is the same map as the
// general acos/atan/pow step for every whole power, including on the y axis (atan(0, 0)) and
// at the origin; and the power-8 orbit through it agrees with the trigonometric orbit after
// every iteration count. It fails if the step used another angle convention (e.g. phi from
// atan(x, z)) or the wrong r^(n-1).
TEST_CASE("sdf double: mandelbulb's whole-power step equals the trigonometric step", "[sdf][double]") {
  using sdf64::vec3;
  ref::Sampler s;
  double worstStep = 0, worstD = 0, worstTrap = 0;
  int inside = 0;
  for (int i = 0; i < 4000; ++i) {
    glm::dvec3 p = s.point(1.4);
    if (i % 50 == 0) p = glm::dvec3(0.0, p.y, 0.0);   // on the axis: rho = 0
    if (i == 1) p = glm::dvec3(0.0);
    int n = 1 + i % 15;
    double r = glm::length(p);
    auto whole = sdf64::mandelbulbPowInt(vec3(p), r, n);
    auto trig = sdf64::mandelbulbPowTrig(vec3(p), r, double(n));
    INFO("p=(" << p.x << "," << p.y << "," << p.z << ") n=" << n);
    worstStep = std::max(worstStep, double(glm::length(whole - trig)) / std::max(1.0, std::pow(r, n)));
    int iters = 1 + i % 12;
    const double bound8 = sdf64::mandelbulbBoundingRadius(8.0);
    auto orbit8 = sdf64::mandelbulbOrbit(vec3(p), 8.0, iters, true, bound8);
    auto orbitTrig = sdf64::mandelbulbOrbit(vec3(p), 8.0, iters, false, bound8);
    REQUIRE(std::isfinite(double(orbit8.x)));
    worstD = std::max(worstD, std::abs(double(orbit8.x - orbitTrig.x)) / std::max(1.0, std::abs(double(orbitTrig.x))));
    worstTrap = std::max(worstTrap, std::abs(double(orbit8.y - orbitTrig.y)));
    if (orbitTrig.x < 0.05) ++inside;
  }
  CHECK(worstStep < 1e-12);
  CHECK(inside > 100);   // the sample reaches the surface, where the orbit is longest
  CHECK(worstD < 1e-6);
  CHECK(worstTrap < 1e-6);
  // fMandelbulbTrap takes the whole step for power 8 only
  vec3 q(0.3, 0.6, -0.4);
  for (double n : {8.0, 8.5, 7.0})
    CHECK(sdf64::fMandelbulbTrap(q, n, 8).x == sdf64::mandelbulbOrbit(q, n, 8, n == 8.0, sdf64::mandelbulbBoundingRadius(n)).x);
}
