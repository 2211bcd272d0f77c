// The record of preparation steps kept in a heightfield's provenance.
#include <string>

#include "glintscope/prepare/prepare.hpp"

namespace glintscope {

void record_preparation(Heightfield& field, const std::string& description) {
    // Numbered after the steps already recorded, so a field prepared in two runs keeps both.
    int step = 1;
    while (field.provenance.count("prepare." + std::to_string(step)) != 0) ++step;
    field.provenance["prepare." + std::to_string(step)] = description;
}

}  // namespace glintscope
