#pragma once
// The explicit table of methods (no self-registration: one line per method in method_table.cpp)
// and the checks the pipeline makes against it, for entry points above the pipeline that run a
// method's machinery themselves (the discrete method's glint map).
#include <vector>

#include "lobe/method.hpp"

namespace glintscope {

const std::vector<MethodEntry>& method_table();

// The whole-field footprint only for methods that take it, and only the method's own option keys;
// each throws Error naming the method and what it accepts.
void check_footprint(const MethodInfo& method, const Footprint& footprint);
void check_option_keys(const MethodInfo& method, const LobeQuery& query);

}  // namespace glintscope
