// accuracy: how far a render is from the truth, and what the quality knobs cost.
//
// - The four scenes + render.glsl compiled as C++ (cpu_scene.h): the CPU double build is the
//   reference raymarcher (tight epsilon, many steps, under-relaxed); the float build mirrors
//   the GPU's precision for CPU-side stability tests.
// - Geometry from the GPU: a DEBUG_VIEW 4 program renders (t, octahedral normal, steps) into a
//   RGBA32F target; DecodeGeometry reads it. CompareGeometry gives the metrics:
//   hit-distance error in pixel footprints (t * pixel angle), silhouette mismatch, normal angle
//   error, rays out of steps. CompareRgba8 gives PSNR and % pixels more than 8/255 off.
// - RunSweep: every knob setting of SweepSettings(), timed like `sdfvj bench` (GL_TIME_ELAPSED,
//   or glFinish + wall clock on llvmpipe) at the bench size, geometry compared with the CPU
//   reference at the reference size, image compared with a 4096-step GPU render.
// - Reports: CSV, time-against-error plots (PNG and SVG, Pareto front marked), docs/accuracy.md.
// Needs only EGL/libepoxy/glm/json: it is part of sdfvj-headless.
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "accuracy/cpu_scene.h"
#include "render/render.h"
#include "scene/scene.h"

namespace sdfvj::accuracy {

// printf-style formatting of one number ("%.3f") for the reports and the sweep's labels.
std::string Format(const char* format, double v);


// ---- CPU build of the scenes ------------------------------------------------------------
// Generated from shaders/scenes/*.glsl at configure time: equals ListScenes() of the source tree.
std::vector<std::string> CpuSceneNames();
bool HasCpuScene(const std::string& name);
CpuScene<float> MakeCpuScene32(const std::string& name);    // name must pass HasCpuScene (a bug otherwise)
CpuScene<double> MakeCpuScene64(const std::string& name);
// The scene reads SCENE_GLOBAL_LIPSCHITZ: it has a raw-field build with a global bound
// (MakeCpuSceneGlobal32), which the sweep's "plain" row marches as a plain raymarcher would.
bool HasGlobalLipschitzBuild(const std::string& name);
CpuScene<float> MakeCpuSceneGlobal32(const std::string& name);   // falls back to MakeCpuScene32
CpuScene<double> MakeCpuSceneGlobal64(const std::string& name);  // falls back to MakeCpuScene64

// Sets every uniform the way FrameRenderer::Draw does for (scene, in) at width x height
// (parameters clamped to their declared range).
template <class S>
void ApplyFrame(CpuScene<S>& s, const SceneInfo& scene, const FrameInputs& in, int width, int height) {
    using V3 = typename CpuScene<S>::V3;
    auto v3 = [](const Vec3f& v) { return V3(S(v[0]), S(v[1]), S(v[2])); };
    *s.time = S(float(in.time)); *s.frame = in.frame; *s.beat = S(in.beat);
    *s.resolution = typename CpuScene<S>::V2(S(width), S(height));
    *s.camPos = v3(scene.camPos); *s.camTarget = v3(scene.camTarget); *s.fov = S(scene.fov);
    *s.lightDir = v3(scene.lightDir); *s.lightColor = v3(scene.lightColor);
    *s.roughness = S(scene.roughness); *s.metalness = S(scene.metalness);
    const Quality& q = in.quality;
    *s.maxSteps = q.maxSteps; *s.hitEps = S(q.hitEps); *s.maxDist = S(q.maxDist); *s.stepFactor = S(q.stepFactor);
    *s.fixedStep = S(q.fixedStep); *s.shadowSteps = q.shadowSteps; *s.shadowK = S(q.shadowK);
    *s.aoSamples = q.aoSamples; *s.normalEps = S(q.normalEps); *s.effectsOff = in.effectsOff;
    for (const ParamDecl& d : scene.params) {
        float v = d.defaultValue;
        for (const auto& [name, value] : in.params)
            if (name == d.name) v = ClampParam(d, value);
        auto it = s.inputs.find(d.name);
        if (it != s.inputs.end()) *it->second = S(v);
    }
}

// Runs f(y) for every row on `threads` threads (0 = hardware concurrency).
void ParallelRows(int height, int threads, const std::function<void(int)>& f);

// ---- geometry --------------------------------------------------------------------------
struct GeomPixel {
    float t = -1.0f;          // distance along the ray, -1 on a miss
    float steps = 0.0f;
    bool hit = false;
    bool outOfSteps = false;
    float n[3] = {0.0f, 1.0f, 0.0f};
};
struct Geometry {
    int width = 0, height = 0;
    std::vector<GeomPixel> px;   // row-major, BOTTOM row first (row y has fragCoord.y = y + 0.5)
};

struct ReferenceSettings {
    int maxSteps = 20000;
    double hitEps = 1e-6;        // relative (EPS_MODE 0): eps * max(1, t)
    double stepFactor = 0.5;     // under-relaxed on top of the scene's Lipschitz bound
    // Central differences at the renderer's default offset (1e-3 * max(1, t)), in double: on smooth
    // surfaces within 1e-4 deg of the analytic normal (MeasureNormals), and on the Mandelbulb, whose
    // DE normal depends on the scale it is taken at, the same scale as the default renderer.
    double normalEps = 1e-3;
};
// The CPU double reference of a frame's primary rays.
Geometry CpuReferenceGeometry(const SceneInfo& scene, const FrameInputs& in, int width, int height,
                              const ReferenceSettings& r = {}, int threads = 0);
// The RGBA32F output of a DEBUG_VIEW 4 program (FrameRenderer::ReadPixelsFloat).
Geometry DecodeGeometry(const std::vector<float>& rgba, int width, int height);
// Vertical angle of one pixel for the scene's camera at this frame height.
double PixelAngle(const SceneInfo& scene, int height);

struct GeometryError {
    double tErrP50 = 0, tErrP99 = 0, tErrMax = 0;   // |t - t_ref| / (t_ref * pixel angle), both hit
    double silhouettePct = 0;                       // hit/miss disagreement, % of pixels
    double normalP50 = 0, normalP99 = 0;            // degrees, both hit
    double outOfStepsPct = 0;                       // of the tested geometry
    double refOutOfStepsPct = 0;                    // of the reference (should be ~0)
    int bothHit = 0;
};
GeometryError CompareGeometry(const Geometry& test, const Geometry& ref, double pixelAngle);

struct ImageError {
    double psnr = 0;        // dB over RGB (99 if identical)
    double pctOver8 = 0;    // % pixels with any channel more than 8/255 off
};
ImageError CompareRgba8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b);
// An RGBA8 image of w x h (even) averaged 2x2 (rounded): w/2 x h/2, what a supersampled frame shows.
std::vector<uint8_t> DownsampleRgba8x2(const std::vector<uint8_t>& rgba, int w, int h);

// Counts non-finite floats; `firstBad` gets the first pixel index when any.
size_t CountNonFinite(const std::vector<float>& v, size_t* firstBad = nullptr);

// ---- normal estimators against analytic normals ---------------------------------------
struct NormalStats {
    std::string precision, shape, method;   // float|double, sphere|box|torus, central|forward|tetrahedron
    double eps = 0;                         // finite-difference offset (absolute: t = 1)
    double p50 = 0, p99 = 0, max = 0;       // angle error, degrees
    int nonFinite = 0;
};
// Random surface points of a unit sphere, a box (faces, away from edges) and a torus (R 1,
// r 0.3); every method at offsets 1e-2, 1e-3, 1e-4, in float and double. Ordered so that
// each consecutive triple is central, forward, tetrahedron for one (precision, shape, eps).
std::vector<NormalStats> MeasureNormals(int samples = 2000);
std::string NormalStatsMarkdown(const std::vector<NormalStats>& stats);

// ---- GPU -------------------------------------------------------------------------------
// Assembles and builds a variant with extra "#define NAME VALUE" lines after #version
// (e.g. "EPS_MODE 2") — knobs the bench needs that are not part of EffectSet.
bool BuildProgram(const SceneInfo& scene, const EffectSet& effects, RenderPath path,
                  const std::vector<std::string>& extraDefines, Program* out, std::string* error);

// ---- the sweep -------------------------------------------------------------------------
struct Setting {
    std::string knob;        // "steps", "eps_relative", "eps_fixed", "eps_pixel", "normals", ...
    std::string label;       // "steps=256"
    Quality q;
    int normals = -1;        // NORMALS; -1: the scene's (its header's "NORMALS", else central)
    bool marchFixed = false;
    int epsMode = 0;         // EPS_MODE
    bool naiveStep = false;  // step factor multiplied back by the scene's Lipschitz bound
    bool bounds = true;      // BOUNDS: use the scene's bounding volume (render.glsl)
    std::string role;        // "default" (sdfvj's Quality{}), "plain" (seed raymarcher) or ""
    std::vector<std::string> defines;   // extra "#define NAME VALUE" lines of this row's program
    // Render scale (knob "scale"): the frame is drawn at round(width x scale) x round(height x
    // scale) and resampled to the sweep's size with a linear blit, as `live --render-scale` shows
    // it (2: supersampled, each pixel the mean of 2x2). Such a row's image is compared with the
    // supersampled truth (the 4096-step render at twice the size, averaged 2x2), not with the
    // one-sample 4096-step render, and its geometry columns are the default row's (a scale
    // changes which rays are cast, not how each is marched).
    float scale = 1.0f;
};
// which: "full" (every knob), "tiny" (a handful, for the test suite), "scale" (the default and
// the render scales only) or "looks" (the default and the look rows: penumbra, AO samples).
std::vector<Setting> SweepSettings(const std::string& which);

struct Row {
    std::string scene;
    Setting s;
    double gpuMs = 0;
    GeometryError g;
    ImageError img;
    // Against the scene's own look (the 4096-step render at the default penumbra and AO samples):
    // the same as img but on the look rows (penumbra, AO samples), where it adds what the look
    // changed. What `live --frame-budget` counts: fewer AO samples are not free.
    ImageError imgSceneLook;
    bool pareto = false;
};

struct SweepOptions {
    std::vector<std::string> scenes = {"primitives", "midi", "character", "mandelbulb"};
    int width = 1920, height = 1080;           // timing and image size
    int refWidth = 0, refHeight = 0;           // CPU reference size (0 = same as width x height)
    std::string sweep = "full";
    std::string path = "auto";                 // auto, fragment, compute
    int frames = 10, warmup = 3;
    double time = 1.0;
    std::vector<std::pair<std::string, float>> params;   // overrides (clamped)
    int threads = 0;
    std::function<void(const std::string&)> log;  // progress lines
};
struct SweepInfo {
    std::string device;          // context description
    bool wallClock = false;
    std::string path;            // render path used
    double refSeconds = 0;       // CPU reference time
    // Scenes with a bounding volume: the 4096-step render with the bound against the one
    // without (the bound's own effect on the image; rows are compared with the reference of
    // their own BOUNDS setting).
    std::map<std::string, ImageError> boundEffect;
    // Drift check per scene: the first setting timed alone (median of `frames`) before the
    // interleaved rounds and again after them, ms. Over 3 % apart, the scene's times are suspect.
    std::map<std::string, std::pair<double, double>> drift;
};
// Needs a current GL context (HeadlessContext). False with a reason on failure.
bool RunSweep(const SweepOptions& o, std::vector<Row>* rows, SweepInfo* info, std::string* error);

// Marks, per scene, the rows on the Pareto front of (gpuMs, pctOver8); render-scale rows, whose
// error is against another truth, form a front of their own.
void MarkPareto(std::vector<Row>* rows);

// ---- reports ---------------------------------------------------------------------------
std::string CsvHeader();
std::string CsvLine(const Row& r);
bool WritePlotPng(const std::string& path, const std::vector<Row>& rows, const std::string& scene, std::string* error);
std::string PlotSvg(const std::vector<Row>& rows, const std::string& scene);
std::string MarkdownReport(const std::vector<Row>& rows, const SweepOptions& o, const SweepInfo& info,
                           const std::string& commandLine);

}  // namespace sdfvj::accuracy
