// Crossfade: two rendered frames mixed into a third target (a scene change that morphs).
#include <epoxy/gl.h>

#include "render/gl_stages.h"
#include "render/render.h"

namespace sdfvj {

namespace {

// A full-screen triangle from gl_VertexID; the fragment mixes two textures by u_mix.
const char* kVertex = R"(#version 450 core
out vec2 uv;
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";
const char* kFragment = R"(#version 450 core
in vec2 uv;
out vec4 color;
layout(binding = 0) uniform sampler2D u_from;
layout(binding = 1) uniform sampler2D u_to;
uniform float u_mix;
void main() { color = mix(texture(u_from, uv), texture(u_to, uv), u_mix); }
)";

}  // namespace

Crossfade::~Crossfade() {
    if (program_) glDeleteProgram(program_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
}

bool Crossfade::Init(std::string* error) {
    if (program_) return true;
    std::string log;
    unsigned vs = CompileStage(GL_VERTEX_SHADER, kVertex, &log);
    unsigned fs = vs ? CompileStage(GL_FRAGMENT_SHADER, kFragment, &log) : 0;
    unsigned p = vs && fs ? LinkStages({vs, fs}, &log) : 0;
    if (!p) {
        if (vs && !fs) glDeleteShader(vs);
        *error = "crossfade program: " + log;
        return false;
    }
    program_ = p;
    mixLocation_ = glGetUniformLocation(p, "u_mix");
    glGenVertexArrays(1, &vao_);
    return true;
}

void Crossfade::Draw(unsigned fromTexture, unsigned toTexture, float t, unsigned targetFramebuffer, int width,
                     int height) {
    if (!program_) return;
    glBindFramebuffer(GL_FRAMEBUFFER, targetFramebuffer);
    glViewport(0, 0, width, height);
    SetOverwriteBlend();
    glUseProgram(program_);
    glUniform1f(mixLocation_, t);
    glBindTextureUnit(0, fromTexture);
    glBindTextureUnit(1, toTexture);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
}

}  // namespace sdfvj
