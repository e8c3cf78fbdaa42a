// reference_geometry.h - independent double-precision ground truth for the SDF tests:
// exact distances to convex polytopes, capped cylinders, circles and ellipsoids computed
// without the library's formulas (closest points, face polygons, surface search).
#pragma once
#include <glm/glm.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace ref {

using glm::dvec2;
using glm::dvec3;

inline double segmentDistance(dvec3 p, dvec3 a, dvec3 b) {
  dvec3 ab = b - a;
  double len2 = glm::dot(ab, ab);
  double t = len2 > 0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + ab * t));
}

// A convex planar polygon (vertices in order) as one face of a polytope.
struct Face {
  std::vector<dvec3> v;
  dvec3 n;  // outward unit normal
};

// Unsigned distance to a convex planar polygon.
inline double faceDistance(dvec3 p, const Face& f) {
  double h = glm::dot(p - f.v[0], f.n);
  dvec3 q = p - f.n * h;  // projection into the face plane
  bool inside = true;
  for (size_t i = 0; i < f.v.size(); ++i) {
    dvec3 a = f.v[i], b = f.v[(i + 1) % f.v.size()];
    if (glm::dot(glm::cross(b - a, q - a), f.n) < 0) inside = false;
  }
  if (inside) return std::abs(h);
  double d = std::numeric_limits<double>::max();
  for (size_t i = 0; i < f.v.size(); ++i) d = std::min(d, segmentDistance(p, f.v[i], f.v[(i + 1) % f.v.size()]));
  return d;
}

// Signed distance to a convex polytope given by its faces: outside, the distance to the
// nearest face polygon; inside, minus the distance to the nearest face plane.
inline double polytopeDistance(dvec3 p, const std::vector<Face>& faces) {
  double maxPlane = -std::numeric_limits<double>::max();
  for (auto& f : faces) maxPlane = std::max(maxPlane, glm::dot(p - f.v[0], f.n));
  if (maxPlane <= 0) return maxPlane;
  double d = std::numeric_limits<double>::max();
  for (auto& f : faces) d = std::min(d, faceDistance(p, f));
  return d;
}

// Right prism: convex polygon (counter-clockwise in XY) extruded to z in [-h, h].
inline std::vector<Face> prism(const std::vector<dvec2>& poly, double h) {
  std::vector<Face> faces;
  Face top, bottom;
  for (auto& v : poly) top.v.push_back(dvec3(v, h));
  for (auto it = poly.rbegin(); it != poly.rend(); ++it) bottom.v.push_back(dvec3(*it, -h));
  top.n = dvec3(0, 0, 1);
  bottom.n = dvec3(0, 0, -1);
  faces.push_back(top);
  faces.push_back(bottom);
  for (size_t i = 0; i < poly.size(); ++i) {
    dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
    dvec2 e = b - a;
    Face side;
    side.v = {dvec3(a, -h), dvec3(b, -h), dvec3(b, h), dvec3(a, h)};
    side.n = glm::normalize(dvec3(e.y, -e.x, 0));
    faces.push_back(side);
  }
  return faces;
}

inline std::vector<Face> box(dvec3 b) {
  // a box is the rectangle prism, rotated so that its Z extent is b.z
  return prism({{-b.x, -b.y}, {b.x, -b.y}, {b.x, b.y}, {-b.x, b.y}}, b.z);
}

// Regular hexagon with flat top/bottom and apothem a (vertices at angles 0, 60, ...).
inline std::vector<dvec2> hexagon(double a) {
  std::vector<dvec2> v;
  double r = a * 2.0 / std::sqrt(3.0);
  for (int i = 0; i < 6; ++i) v.push_back(r * dvec2(std::cos(i * M_PI / 3), std::sin(i * M_PI / 3)));
  return v;
}

// Equilateral triangle, apex up, inradius a, centred on its incentre.
inline std::vector<dvec2> triangle(double a) {
  return {{-a * std::sqrt(3.0), -a}, {a * std::sqrt(3.0), -a}, {0, 2 * a}};
}

// Capped cylinder around Y: distance to the rectangle [0, r] x [-h, h] in (rho, y).
inline double cylinder(dvec3 p, double r, double h) {
  double rho = std::hypot(p.x, p.z), y = std::abs(p.y);
  if (rho <= r && y <= h) return -std::min(r - rho, h - y);
  double cx = std::min(rho, r), cy = std::min(y, h);
  return std::hypot(rho - cx, y - cy);
}

// Torus: distance to the nearest point of the ring circle, minus the tube radius.
inline double torus(dvec3 p, double tube, double ring) {
  dvec3 radial(p.x, 0, p.z);
  double l = glm::length(radial);
  dvec3 c = l > 0 ? radial * (ring / l) : dvec3(ring, 0, 0);
  return glm::length(p - c) - tube;
}

// Unsigned distance to an ellipsoid surface by a dense (theta, phi) search refined by a
// shrinking pattern search: accurate to ~1e-9 for the sizes used in the tests.
inline double ellipsoidSurfaceDistance(dvec3 p, dvec3 r) {
  auto at = [&](double th, double ph) {
    return glm::length(p - dvec3(r.x * std::sin(th) * std::cos(ph), r.y * std::cos(th), r.z * std::sin(th) * std::sin(ph)));
  };
  double bt = 0, bp = 0, best = std::numeric_limits<double>::max();
  const int N = 120;
  for (int i = 0; i <= N; ++i)
    for (int j = 0; j < 2 * N; ++j) {
      double th = M_PI * i / N, ph = M_PI * j / N, d = at(th, ph);
      if (d < best) best = d, bt = th, bp = ph;
    }
  for (double s = M_PI / N; s > 1e-12; s *= 0.5) {
    bool moved = true;
    while (moved) {
      moved = false;
      for (int k = 0; k < 8; ++k) {
        double th = bt + s * std::cos(k * M_PI / 4), ph = bp + s * std::sin(k * M_PI / 4);
        double d = at(th, ph);
        if (d < best) best = d, bt = th, bp = ph, moved = true;
      }
    }
  }
  return best;
}

// Reproducible random points in a box.
struct Sampler {
  std::mt19937_64 rng{12345};
  dvec3 point(double half) {
    std::uniform_real_distribution<double> u(-half, half);
    return dvec3(u(rng), u(rng), u(rng));
  }
  double range(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  dvec3 direction() {
    std::normal_distribution<double> n;
    return glm::normalize(dvec3(n(rng), n(rng), n(rng)));
  }
};

// Largest |f(a) - f(b)| / |a - b| over random close pairs in a cube of half-size `half`.
template <class F>
double worstLipschitz(F f, double half, int n = 20000) {
  ref::Sampler s;
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    glm::dvec3 a = s.point(half);
    glm::dvec3 b = a + s.direction() * s.range(1e-3, 0.2);
    worst = std::max(worst, std::abs(f(a) - f(b)) / glm::length(a - b));
  }
  return worst;
}

}  // namespace ref
