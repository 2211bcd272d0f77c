#pragma once
// The table of lobe methods. Each method lives in its own file and is listed here once.
#include <string>
#include <vector>

#include "glintscope/lobe.hpp"

namespace glintscope {

struct LobeMethodEntry {
    std::string name;
    std::string description;
    LobeMethod compute;
};

const std::vector<LobeMethodEntry>& lobe_method_table();

}  // namespace glintscope
