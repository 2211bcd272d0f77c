#pragma once
// The explicit table of methods: one line per method in method_table.cpp (no self-registration).
#include <vector>

#include "lobe/method.hpp"

namespace glintscope {

const std::vector<MethodEntry>& method_table();

}  // namespace glintscope
