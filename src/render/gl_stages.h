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

}  // namespace sdfvj
