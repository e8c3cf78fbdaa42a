// cpu_scene.h - one scene plus render/render.glsl compiled as C++ (float or double), reached
// through pointers to its uniforms and std::functions for map, march and normals. The CPU
// double build is the accuracy reference; the float build mirrors the GPU's precision.
// Instantiated by scene_instance.inc (one namespace per scene and precision).
#pragma once
#include "sdf/glsl_glm.h"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace sdfvj::accuracy {

// One marched ray as the renderer sees it.
template <class S>
struct CpuRay {
    S t = 0;          // distance along the ray (u_maxDist on a miss)
    S steps = 0;      // map evaluations
    bool hit = false;
};

template <class S>
struct CpuScene {
    using V2 = glm::vec<2, S>;
    using V3 = glm::vec<3, S>;
    using V4 = glm::vec<4, S>;
    std::string name;
    std::function<V4(V3)> map;
    std::function<S()> lipschitz;
    std::function<V4(V2)> render;                   // render.glsl at its default switches
    std::function<V4(V2, S)> renderFrom;            // the same, the primary ray starting at t (cone pre-pass)
    std::function<S(V2, V2)> coneStart;             // the cone pre-pass: start distance of a tile (pixel centres lo, hi)
    std::function<S(V2, V2)> coneStartUnfolded;     // ... as CONE_MIRROR runs it with reflections: through the floor (march.glsl)
    bool hasUnfoldedCone = false;                   // the scene has that cone (objects over a floor: SCENE_OBJECTS)
    std::function<V3(V2)> cameraRay;                // unit ray through a pixel
    std::function<CpuRay<S>(V3, V3, S)> march;      // ro, rd, tmin (sphere tracing, EPS_MODE 0)
    std::function<CpuRay<S>(V3, V3, S)> marchWhole; // the same, ignoring the scene's bounding volume
    std::function<S(V3, V3)> softShadow;            // ro, light dir: shadowSoft over render.glsl's shadowRange
    std::function<S(V3, V3)> softShadowWhole;       // shadowSoft over all of [0.01, u_maxDist]
    std::function<V2(V3, V3)> shadowRange;          // ro, light dir: the stretch softShadow marches (empty: x > y)
    bool hasBound = false;                          // the scene declares a bounding sphere (SCENE_BOUND)
    std::function<V4()> sceneBound;                 // centre xyz, radius w (or 0 without one)
    bool hasBox = false;                            // ... and a box (SCENE_BOX)
    std::function<V3()> sceneBoxMin, sceneBoxMax;   // its corners (or 0 without one)
    std::function<S(S)> hitEpsilon;
    std::function<V3(V3, S)> normalCentral, normalForward, normalTetra;  // p, eps
    std::function<V3(V3, S)> surfaceNormal;         // p, t (central, u_normalEps * max(1, t))
    std::map<std::string, S*> inputs;               // u_<name> of every header input
    S* time; int* frame; V2* resolution; S* beat; V3* camPos; V3* camTarget; S* fov;
    V3* lightDir; V3* lightColor; int* maxSteps; S* hitEps; S* maxDist; S* stepFactor;
    S* fixedStep; int* shadowSteps; S* shadowK; int* aoSamples; S* normalEps; S* roughness;
    S* metalness; int* effectsOff;
};

// One scene's CPU builds, generated from shaders/scenes/NAME.glsl at configure time
// (src/accuracy/CMakeLists.txt): nothing in src/accuracy names a scene by hand.
struct CpuSceneBuild {
    std::string name;                               // the scene file's stem, as ListScenes() gives it
    std::function<CpuScene<float>()> make32;
    std::function<CpuScene<double>()> make64;
    // The raw field with a global Lipschitz bound, for scenes that read SCENE_GLOBAL_LIPSCHITZ
    // (they divide a non-Lipschitz part by its own bound by default); empty otherwise.
    std::function<CpuScene<float>()> makeGlobal32;
    std::function<CpuScene<double>()> makeGlobal64;
};
// Every scene in shaders/scenes at configure time, sorted by name (cpu_scene_table.cpp).
const std::vector<CpuSceneBuild>& CpuSceneBuilds();

}  // namespace sdfvj::accuracy
