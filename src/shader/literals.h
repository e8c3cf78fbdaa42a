// literals.h - a scene's float constants as uniforms, so a save that only retunes numbers needs
// no compile (LiveProgram's literal tier; docs/performance.md "Retuning a constant").
//
//   LiftedText a = LiftLiterals(sceneText);   // "... 0.55f ..." -> "... u_lit[3] ...", values[3] = 0.55f
//   if (a.text == LiftLiterals(savedText).text)   // same skeleton: only literal values changed
//       upload LiftLiterals(savedText).values to the program built from a.text
//
// Lifted: float literals (a '.' or an exponent: 1.0, .5, 2e-3, 0.55f) inside function bodies.
// Left as they are (an edit there changes the skeleton, so it compiles as usual): literals outside
// any function (global consts, layout), in `const` declarations (GLSL wants constant expressions
// there), on preprocessor lines (#define, #if), in comments (the JSON header), integer literals
// (array sizes, loop counts, switch labels), doubles (the lf suffix), and any past kMaxLifted.
// Lines and line breaks are kept, so the driver's messages still name the right line.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace sdfvj {

struct LiftedText {
    std::string text;            // the source with each lifted literal replaced by u_lit[i]
    std::vector<float> values;   // values[i]: the literal u_lit[i] stands for, parsed as GLSL does (nearest float)
};

constexpr size_t kMaxLifted = 256;   // uniform components are a limited resource (GL guarantees 1024 per stage)

LiftedText LiftLiterals(const std::string& text);

// The first float literal that LiftLiterals would lift: [*begin, *end) in `text`. False if none.
bool FindFirstLiftable(const std::string& text, size_t* begin, size_t* end);

}  // namespace sdfvj
