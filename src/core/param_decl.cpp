#include "core/param_decl.h"

#include <algorithm>
#include <cmath>

namespace sdfvj {

float ClampParam(const ParamDecl& decl, float value) {
    const float lo = std::min(decl.minValue, decl.maxValue), hi = std::max(decl.minValue, decl.maxValue);
    if (!std::isfinite(value)) value = decl.defaultValue;   // NaN/Inf never reach a shader
    if (!std::isfinite(value)) value = lo;
    if (decl.type == ParamType::Bool) return value >= 0.5f ? 1.0f : 0.0f;
    if (decl.type == ParamType::Int) value = std::round(value);
    return std::clamp(value, lo, hi);
}

}  // namespace sdfvj
