#include "render/gl_stages.h"

#include <epoxy/gl.h>

#include <atomic>

#include "render/live_program.h"
#include "render/render.h"

namespace sdfvj {

std::string ShaderLog(unsigned shader) {
    GLint len = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
    std::string buf(len > 1 ? (size_t)len : 1, '\0');
    glGetShaderInfoLog(shader, (GLsizei)buf.size(), nullptr, buf.data());
    return buf.c_str();
}

std::string ProgramLog(unsigned program) {
    GLint len = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
    std::string buf(len > 1 ? (size_t)len : 1, '\0');
    glGetProgramInfoLog(program, (GLsizei)buf.size(), nullptr, buf.data());
    return buf.c_str();
}

unsigned CompileStage(unsigned kind, const char* text, std::string* rawLog) {
    unsigned s = glCreateShader(kind);
    glShaderSource(s, 1, &text, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (ok) return s;
    *rawLog += ShaderLog(s);
    glDeleteShader(s);
    return 0;
}

unsigned LinkStages(std::initializer_list<unsigned> stages, std::string* rawLog) {
    unsigned p = glCreateProgram();
    for (unsigned s : stages) glAttachShader(p, s);
    glLinkProgram(p);
    for (unsigned s : stages) glDeleteShader(s);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (ok) return p;
    *rawLog = ProgramLog(p);
    glDeleteProgram(p);
    return 0;
}

namespace {
std::atomic<int> overwriteBlendOverride{-1};
}

void SetOverwriteBlendOverride(int mode) { overwriteBlendOverride.store(mode < 0 ? -1 : mode > 0 ? 1 : 0); }

bool OverwriteBlendOn() {
    if (const int o = overwriteBlendOverride.load(); o >= 0) return o == 1;
    static std::atomic<int> on{-1};   // -1: not decided yet (no context was current)
    int v = on.load();
    if (v < 0) {
        if (!glGetString(GL_RENDERER)) return false;
        v = EnvSwitch("SDFVJ_IDENTITY_BLEND", IsSoftwareRenderer()) ? 1 : 0;
        on.store(v);
    }
    return v == 1;
}

void SetOverwriteBlend() {
    if (!OverwriteBlendOn()) {
        glDisable(GL_BLEND);
        return;
    }
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ZERO);
}

}  // namespace sdfvj
