// One program built and used once, every step timed (bench_build.h).
#include "app/bench_build.h"

#include <epoxy/gl.h>

#include <algorithm>

#include "app/bench_support.h"
#include "render/compile_worker.h"

namespace sdfvj {

namespace {

std::string InfoLog(GLuint object, bool program) {
    GLint n = 0;
    if (program) glGetProgramiv(object, GL_INFO_LOG_LENGTH, &n);
    else glGetShaderiv(object, GL_INFO_LOG_LENGTH, &n);
    std::string log((size_t)std::max(n, 1), '\0');
    if (program) glGetProgramInfoLog(object, n, nullptr, log.data());
    else glGetShaderInfoLog(object, n, nullptr, log.data());
    return log.substr(0, 400);
}

}  // namespace

BuildSteps TimedBuild(const std::function<void(unsigned)>& feed, const char* step, RenderPath path) {
    BuildSteps s;
    const bool compute = path == RenderPath::Compute;
    auto t0 = Clock::now();
    const GLuint sh = glCreateShader(compute ? GL_COMPUTE_SHADER : GL_FRAGMENT_SHADER);
    feed(sh);
    GLuint vs = 0;
    if (!compute) {
        vs = glCreateShader(GL_VERTEX_SHADER);
        const char* text = FullscreenVertexShader();
        glShaderSource(vs, 1, &text, nullptr);
        glCompileShader(vs);
    }
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    s.compile = MsSince(t0);
    if (!ok) {
        s.error = std::string(step) + ": " + InfoLog(sh, false);
        glDeleteShader(sh);
        if (vs) glDeleteShader(vs);
        return s;
    }
    const GLuint prog = glCreateProgram();
    glAttachShader(prog, sh);
    if (vs) glAttachShader(prog, vs);
    t0 = Clock::now();
    glLinkProgram(prog);
    GLint linked = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &linked);
    s.link = MsSince(t0);
    if (linked) {
        t0 = Clock::now();
        PrimeProgram(prog, path, false);
        glFinish();
        s.use = MsSince(t0);
        s.ok = true;
    } else {
        s.error = "link: " + InfoLog(prog, true);
    }
    glDeleteProgram(prog);
    glDeleteShader(sh);
    if (vs) glDeleteShader(vs);
    return s;
}

BuildSteps TimedGlslBuild(const std::string& text, RenderPath path) {
    return TimedBuild([&](unsigned sh) {
        const char* p = text.c_str();
        glShaderSource(sh, 1, &p, nullptr);
        glCompileShader(sh);
    }, "compile", path);
}

}  // namespace sdfvj
