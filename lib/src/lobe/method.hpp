#pragma once
// What a method author writes: one MethodEntry, declared in the method's own file, and one line
// in the method table (method_table.cpp). compute_lobe (compute.cpp) does the generic work, so
// a method's compute function sees a validated query with only its own option keys.
#include <string>
#include <vector>

#include "glintscope/lobe.hpp"

namespace glintscope {

using MethodFunction = LobeImage (*)(const LobeQuery&);

struct MethodEntry {
    MethodInfo info;
    MethodFunction compute = nullptr;  // answers every quantity in info.quantities
};

// The explicit table (no self-registration: the library is static).
const std::vector<MethodEntry>& method_table();

// Checks compute_lobe makes, for entry points that run a method's machinery themselves (e.g. the
// discrete method's glint map): the whole-field footprint only for methods that take it, and only
// the method's own option keys. Each throws Error naming the method and what it accepts.
void check_footprint(const MethodInfo& method, const Footprint& footprint);
void check_option_keys(const MethodInfo& method, const LobeQuery& query);

// Method options as values, with defaults when absent; each throws Error naming the option.
double method_option_number(const LobeQuery& query, const std::string& key, double fallback);
double method_option_length_um(const LobeQuery& query, const std::string& key, double fallback);
int method_option_integer(const LobeQuery& query, const std::string& key, int fallback, int min, int max);
std::string method_option_text(const LobeQuery& query, const std::string& key, const std::string& fallback);

}  // namespace glintscope
