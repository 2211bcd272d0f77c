#pragma once
// Internal to surface/: validate() (heightfield.hpp) and what its pass over the heights found,
// so that the statistics, the areal parameters and the spectra read the heights once for both.
#include <cstddef>
#include <string>

#include "glintscope/surface/heightfield.hpp"

namespace glintscope {

// The valid (non-NaN) heights.
struct ValidHeights {
    std::size_t count = 0;
    double mean = 0.0;
    float lowest = 0.0f, highest = 0.0f;
    bool missing = false;  // count < field.size()
};

// validate(field, what, allow_missing), returning what its one pass (parallel, the same bits on
// any thread count) found of the valid heights.
ValidHeights validated_heights(const Heightfield& field, const std::string& what, bool allow_missing);

}  // namespace glintscope
