// gl_stages.h - compiling GLSL stages and linking them, with the driver's logs.
#pragma once
#include <initializer_list>
#include <string>

namespace sdfvj {

// The driver's info log of a shader stage / a program ("" when it has none).
std::string ShaderLog(unsigned shader);
std::string ProgramLog(unsigned program);

// Compiles one stage (GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER); on failure returns
// 0 and appends the driver's log to *rawLog (the caller maps its lines to files).
unsigned CompileStage(unsigned kind, const char* text, std::string* rawLog);

// Links the stages into a new program and deletes them; on failure returns 0 and sets *rawLog to
// the driver's link log.
unsigned LinkStages(std::initializer_list<unsigned> stages, std::string* rawLog);

// The blend state of a full-screen pass that writes every pixel of its target and reads none (the
// scene's fragment path, ISF passes, the crossfade, the compile thread's first draw of a program).
// llvmpipe compiles a fragment program at its first draw, for that draw's state; with blending off
// the draw is "opaque" and llvmpipe builds the program twice, an edge-tested function and one for
// whole tiles. Blending on as the identity (ONE, ZERO, ADD: the pixel written is the shader's) makes
// it build one: the compile about 40 % shorter, the frame the same (docs/performance.md, session
// 39). Elsewhere, and with SDFVJ_IDENTITY_BLEND=0, blending off. Every draw of a program must use
// this, or llvmpipe compiles it again for the other state. Needs a current context.
void SetOverwriteBlend();
// Whether SetOverwriteBlend turns blending on here (decided once a process, on llvmpipe).
bool OverwriteBlendOn();
// Tests: 1 on, 0 off, -1 as decided above.
void SetOverwriteBlendOverride(int mode);

}  // namespace sdfvj
