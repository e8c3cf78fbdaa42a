#include <epoxy/gl.h>

#include "render/render.h"

namespace sdfvj {

namespace {

unsigned CompileStage(GLenum stage, const std::string& text, std::string* log) {
    GLuint s = glCreateShader(stage);
    const char* p = text.c_str();
    glShaderSource(s, 1, &p, nullptr);
    glCompileShader(s);
    GLint ok = 0, len = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &len);
    if (!ok) {
        std::string buf(len > 1 ? len : 1, '\0');
        glGetShaderInfoLog(s, (GLsizei)buf.size(), nullptr, buf.data());
        *log = buf.c_str();
        glDeleteShader(s);
        return 0;
    }
    return s;
}

}  // namespace

Program::~Program() {
    if (id_) glDeleteProgram(id_);
}

bool Program::Build(const ShaderSource& src, RenderPath path, std::string* log) {
    std::string raw;
    GLuint prog = glCreateProgram();
    std::vector<GLuint> stages;
    if (path == RenderPath::Compute) {
        stages.push_back(CompileStage(GL_COMPUTE_SHADER, src.text, &raw));
    } else {
        stages.push_back(CompileStage(GL_VERTEX_SHADER, FullscreenVertexShader(), &raw));
        if (stages.back()) stages.push_back(CompileStage(GL_FRAGMENT_SHADER, src.text, &raw));
    }
    bool ok = stages.back() != 0;
    if (ok) {
        for (GLuint s : stages) glAttachShader(prog, s);
        glLinkProgram(prog);
        GLint linked = 0, len = 0;
        glGetProgramiv(prog, GL_LINK_STATUS, &linked);
        if (!linked) {
            glGetProgramiv(prog, GL_INFO_LOG_LENGTH, &len);
            std::string buf(len > 1 ? len : 1, '\0');
            glGetProgramInfoLog(prog, (GLsizei)buf.size(), nullptr, buf.data());
            raw = buf.c_str();
            ok = false;
        }
    }
    for (GLuint s : stages)
        if (s) glDeleteShader(s);
    if (!ok) {
        glDeleteProgram(prog);
        *log = MapCompileLog(raw, src);
        if (log->empty()) *log = "shader failed to compile with no message from the driver";
        return false;   // the previous program (if any) stays as it was
    }
    if (id_) glDeleteProgram(id_);
    id_ = prog;
    path_ = path;
    source_ = src;
    uniforms_.clear();
    GLint count = 0;
    glGetProgramiv(prog, GL_ACTIVE_UNIFORMS, &count);
    for (GLint i = 0; i < count; ++i) {
        char name[256];
        GLint size = 0;
        GLenum type = 0;
        glGetActiveUniform(prog, (GLuint)i, sizeof name, nullptr, &size, &type, name);
        uniforms_[name] = Slot{glGetUniformLocation(prog, name), type};
    }
    return true;
}

std::vector<std::string> Program::ActiveUniforms() const {
    std::vector<std::string> names;
    for (const auto& [n, _] : uniforms_) names.push_back(n);
    return names;
}

void Program::Set(const std::string& name, float x) const {
    auto it = uniforms_.find(name);
    if (it == uniforms_.end() || it->second.location < 0) return;
    if (it->second.type == GL_INT || it->second.type == GL_BOOL) glProgramUniform1i(id_, it->second.location, (int)x);
    else if (it->second.type == GL_FLOAT) glProgramUniform1f(id_, it->second.location, x);
}

void Program::Set(const std::string& name, float x, float y) const {
    auto it = uniforms_.find(name);
    if (it != uniforms_.end() && it->second.type == GL_FLOAT_VEC2) glProgramUniform2f(id_, it->second.location, x, y);
}

void Program::Set(const std::string& name, float x, float y, float z) const {
    auto it = uniforms_.find(name);
    if (it != uniforms_.end() && it->second.type == GL_FLOAT_VEC3) glProgramUniform3f(id_, it->second.location, x, y, z);
}

}  // namespace sdfvj
