// glsl_prelude.h - makes the shared GLSL subset (shaders/lib, shaders/scenes,
// shaders/render/render.glsl) compile as C++ against GLM.
//
// Usage (see sdf32.h / sdf64.h):
//     #include "sdf/glsl_glm.h"            // at global scope, once
//     namespace mine {
//     #define SDF_GLSL_DOUBLE 0             // 1: scalar double, vec3 = glm::dvec3
//     #include "sdf/glsl_prelude.h"         // types, overloads, `uniform` -> `static`
//     #if SDF_GLSL_DOUBLE
//     #define float double                  // only while the GLSL files are included
//     #endif
//     #include "lib/primitives.glsl"
//     #undef float
//     #undef uniform                        // do not leak the macro
//     }
//
// No include guard: each inclusion starts a fresh instantiation in the enclosing
// namespace, and it also forgets the lib/ include guards so the same .glsl files can be
// instantiated again in the next namespace of the same translation unit.
//
// What it adds: GLSL type names, every scalar function the subset uses (as non-templates,
// so `max(double, 1.0f)` converts instead of failing template deduction), vector-scalar
// overloads that accept float literals in double mode, and `uniform` defined as `static`
// so shared code may declare `uniform float u_time;` and C++ just assigns sdf32::u_time.

#ifndef GLM_VERSION
#error "include sdf/glsl_glm.h at global scope before including sdf/glsl_prelude.h in a namespace"
#endif

#undef SDF_LIB_COMMON_GLSL
#undef SDF_LIB_PRIMITIVES_GLSL
#undef SDF_LIB_MANDELBULB_GLSL
#undef SDF_LIB_DOMAIN_GLSL
#undef SDF_LIB_COMBINATORS_GLSL
#undef SDF_LIB_SHADING_GLSL
#undef SDF_LIB_FIELD_GLSL
#undef SDF_RENDER_UNIFORMS_GLSL
#undef SDF_RENDER_RENDER_GLSL
#undef SDF_RENDER_MARCH_GLSL
#undef SDF_RENDER_INTERVALS_GLSL
#undef SDF_RENDER_SHADE_GLSL
// what a scene declares for render.glsl (its bounding volume) must not carry over to the next
#undef SCENE_BOUND
#undef SCENE_GROUND

#ifndef SDF_GLSL_DOUBLE
#define SDF_GLSL_DOUBLE 0
#endif

#ifndef uniform
#define uniform static
#endif
// A scene's per-invocation state (sceneSetup() writes it, map() reads it): a GLSL global is private
// to its invocation, so in C++ each thread has its own (the CPU reference renders on many).
#ifndef SCENE_STATE
#define SCENE_STATE static thread_local
#endif
#ifndef SDF_GLSL_CPP
#define SDF_GLSL_CPP 1  // shared code may test `#ifdef SDF_GLSL_CPP` (never needed so far)
#endif

#if SDF_GLSL_DOUBLE
using scalar_t = double;
using vec2 = glm::dvec2;
using vec3 = glm::dvec3;
using vec4 = glm::dvec4;
using mat2 = glm::dmat2;
using mat3 = glm::dmat3;
using mat4 = glm::dmat4;
#else
using scalar_t = float;
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using mat2 = glm::mat2;
using mat3 = glm::mat3;
using mat4 = glm::mat4;
#endif
using ivec2 = glm::ivec2;
using ivec3 = glm::ivec3;
using ivec4 = glm::ivec4;

// ---- scalar functions (non-template: mixed double/float arguments convert) -------------
inline scalar_t abs(scalar_t x) { return std::fabs(x); }
inline int abs(int x) { return x < 0 ? -x : x; }
inline scalar_t sign(scalar_t x) { return scalar_t((x > 0) - (x < 0)); }
inline scalar_t floor(scalar_t x) { return std::floor(x); }
inline scalar_t ceil(scalar_t x) { return std::ceil(x); }
inline scalar_t round(scalar_t x) { return std::round(x); }
inline scalar_t fract(scalar_t x) { return x - std::floor(x); }
inline scalar_t mod(scalar_t x, scalar_t y) { return x - y * std::floor(x / y); }
inline scalar_t min(scalar_t a, scalar_t b) { return b < a ? b : a; }
inline scalar_t max(scalar_t a, scalar_t b) { return a < b ? b : a; }
inline int min(int a, int b) { return b < a ? b : a; }
inline int max(int a, int b) { return a < b ? b : a; }
inline scalar_t clamp(scalar_t x, scalar_t lo, scalar_t hi) { return min(max(x, lo), hi); }
inline int clamp(int x, int lo, int hi) { return min(max(x, lo), hi); }
inline scalar_t mix(scalar_t a, scalar_t b, scalar_t t) { return a + (b - a) * t; }
inline scalar_t step(scalar_t edge, scalar_t x) { return x < edge ? scalar_t(0) : scalar_t(1); }
inline scalar_t smoothstep(scalar_t e0, scalar_t e1, scalar_t x) {
  scalar_t t = clamp((x - e0) / (e1 - e0), scalar_t(0), scalar_t(1));
  return t * t * (scalar_t(3) - scalar_t(2) * t);
}
inline scalar_t sqrt(scalar_t x) { return std::sqrt(x); }
inline scalar_t inversesqrt(scalar_t x) { return scalar_t(1) / std::sqrt(x); }
inline scalar_t pow(scalar_t x, scalar_t y) { return std::pow(x, y); }
inline scalar_t exp(scalar_t x) { return std::exp(x); }
inline scalar_t exp2(scalar_t x) { return std::exp2(x); }
inline scalar_t log(scalar_t x) { return std::log(x); }
inline scalar_t log2(scalar_t x) { return std::log2(x); }
inline scalar_t sin(scalar_t x) { return std::sin(x); }
inline scalar_t cos(scalar_t x) { return std::cos(x); }
inline scalar_t tan(scalar_t x) { return std::tan(x); }
inline scalar_t asin(scalar_t x) { return std::asin(x); }
inline scalar_t acos(scalar_t x) { return std::acos(x); }
inline scalar_t atan(scalar_t y, scalar_t x) { return std::atan2(y, x); }
inline scalar_t atan(scalar_t x) { return std::atan(x); }
inline scalar_t radians(scalar_t deg) { return deg * scalar_t(0.017453292519943295); }
inline scalar_t degrees(scalar_t rad) { return rad * scalar_t(57.29577951308232); }
inline scalar_t length(scalar_t x) { return std::fabs(x); }

// ---- vector functions whose GLM templates reject a float literal in double mode -------
// (With scalar_t = float these tie with GLM's templates and, being non-templates, win.)
#define SDF_GLSL_VEC_FUNCS(V)                                                              \
  inline V min(V a, scalar_t b) { return glm::min(a, V(b)); }                              \
  inline V max(V a, scalar_t b) { return glm::max(a, V(b)); }                              \
  inline V min(V a, V b) { return glm::min(a, b); }                                        \
  inline V max(V a, V b) { return glm::max(a, b); }                                        \
  inline V clamp(V x, scalar_t lo, scalar_t hi) { return glm::clamp(x, V(lo), V(hi)); }    \
  inline V clamp(V x, V lo, V hi) { return glm::clamp(x, lo, hi); }                        \
  inline V mix(V a, V b, scalar_t t) { return a + (b - a) * t; }                           \
  inline V mix(V a, V b, V t) { return a + (b - a) * t; }                                  \
  inline V mod(V x, scalar_t y) { return x - y * glm::floor(x / y); }                      \
  inline V mod(V x, V y) { return x - y * glm::floor(x / y); }                             \
  inline V step(scalar_t e, V x) { return glm::step(V(e), x); }                            \
  inline V step(V e, V x) { return glm::step(e, x); }                                      \
  inline V smoothstep(scalar_t e0, scalar_t e1, V x) { return glm::smoothstep(V(e0), V(e1), x); } \
  inline V pow(V x, V y) { return glm::pow(x, y); }                                        \
  inline V operator+(V a, float b) { return a + scalar_t(b); }                             \
  inline V operator-(V a, float b) { return a - scalar_t(b); }                             \
  inline V operator*(V a, float b) { return a * scalar_t(b); }                             \
  inline V operator/(V a, float b) { return a / scalar_t(b); }                             \
  inline V operator+(float a, V b) { return scalar_t(a) + b; }                             \
  inline V operator-(float a, V b) { return scalar_t(a) - b; }                             \
  inline V operator*(float a, V b) { return scalar_t(a) * b; }                             \
  inline V operator/(float a, V b) { return scalar_t(a) / b; }

#if SDF_GLSL_DOUBLE
SDF_GLSL_VEC_FUNCS(glm::dvec2)
SDF_GLSL_VEC_FUNCS(glm::dvec3)
SDF_GLSL_VEC_FUNCS(glm::dvec4)
#else
// In float mode the arithmetic operators are GLM's own; only the functions are needed.
#define SDF_GLSL_VEC_FUNCS_F(V)                                                            \
  inline V min(V a, float b) { return glm::min(a, V(b)); }                                 \
  inline V max(V a, float b) { return glm::max(a, V(b)); }                                 \
  inline V min(V a, V b) { return glm::min(a, b); }                                        \
  inline V max(V a, V b) { return glm::max(a, b); }                                        \
  inline V clamp(V x, float lo, float hi) { return glm::clamp(x, V(lo), V(hi)); }          \
  inline V clamp(V x, V lo, V hi) { return glm::clamp(x, lo, hi); }                        \
  inline V mix(V a, V b, float t) { return a + (b - a) * t; }                              \
  inline V mix(V a, V b, V t) { return a + (b - a) * t; }                                  \
  inline V mod(V x, float y) { return x - y * glm::floor(x / y); }                         \
  inline V mod(V x, V y) { return x - y * glm::floor(x / y); }                             \
  inline V step(float e, V x) { return glm::step(V(e), x); }                               \
  inline V step(V e, V x) { return glm::step(e, x); }                                      \
  inline V smoothstep(float e0, float e1, V x) { return glm::smoothstep(V(e0), V(e1), x); } \
  inline V pow(V x, V y) { return glm::pow(x, y); }
SDF_GLSL_VEC_FUNCS_F(glm::vec2)
SDF_GLSL_VEC_FUNCS_F(glm::vec3)
SDF_GLSL_VEC_FUNCS_F(glm::vec4)
#undef SDF_GLSL_VEC_FUNCS_F
#endif
#undef SDF_GLSL_VEC_FUNCS

// Vector functions (length, dot, cross, normalize, reflect, sin(vec3), ...) need no
// declaration here: argument-dependent lookup finds GLM's versions for glm:: vector types.
