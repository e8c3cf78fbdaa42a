// Pieces of the full build shared by `live` and `render --replay`: the show's mapping and its
// starting parameter state.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "app/show.h"
#include "control/control.h"

namespace sdfvj {

std::string ResolveMappingPath(const Show& show, const std::string& option);
bool LoadShowMapping(const Show& show, const std::string& option, Mapping* mapping, std::string* error);
ParamState ShowParamState(const Show& show);
void CopyParams(const ParamState& s, std::vector<std::pair<std::string, float>>* out);

}  // namespace sdfvj
