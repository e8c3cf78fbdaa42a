// bench_build.h - one compute program built and used once, every step timed: what the compile
// benches share (`bench spirv`: GLSL against SPIR-V; `bench compile`: which part of a program the
// driver's build time goes to). Runs on the calling thread's context; the drivers' disk caches are
// the caller's to set (SetDriverCaches) and every text should be new to them (NudgeFirstConstant).
#pragma once
#include <functional>
#include <string>

#include "shader/shader.h"

namespace sdfvj {

struct BuildSteps {
    double front = 0;     // outside the driver (glslangValidator for SPIR-V); 0 for GLSL
    double compile = 0;   // glCreateShader to its compile status (glCompileShader, or glSpecializeShader)
    double link = 0;      // glLinkProgram to its link status
    double use = 0;       // the first use: a 1x1 dispatch (PrimeProgram) and glFinish
    bool ok = false;
    std::string error;    // "compile: LOG", "link: LOG" (the driver's, cut short)
    double Total() const { return front + compile + link + use; }
};

// A compute shader whose code `feed` gives it (glShaderSource + glCompileShader, or glShaderBinary +
// glSpecializeShader), then linked and used once; `step` names the feed in an error. On the fragment
// path the shader is a fragment shader, linked with the full-screen vertex shader (compiled in
// `compile` too) and used by a 1x1 draw.
BuildSteps TimedBuild(const std::function<void(unsigned shader)>& feed, const char* step, RenderPath path = RenderPath::Compute);
// The same from GLSL source.
BuildSteps TimedGlslBuild(const std::string& text, RenderPath path = RenderPath::Compute);

}  // namespace sdfvj
