// ParamDecl: one scene parameter as the scene's ISF-style JSON header declares it.
//
// The scene module parses headers into these; mapping, smoothing, uniforms and the overlay
// all read the same list, so a parameter is declared once, in the scene file.
#pragma once
#include <string>
#include <vector>

namespace sdfvj {

enum class ParamType { Float, Bool, Int };

struct ParamDecl {
    std::string name;          // uniform is u_<name>
    ParamType type = ParamType::Float;
    float defaultValue = 0.0f;
    float minValue = 0.0f;
    float maxValue = 1.0f;
    std::string label;         // human-readable, for the overlay
};

// Clamps a value into the declared range (ints rounded, bools to 0/1; NaN/Inf -> the default).
// The one clamp every input path uses: presets, --param, OSC, MIDI mappings.
float ClampParam(const ParamDecl& decl, float value);

}  // namespace sdfvj
