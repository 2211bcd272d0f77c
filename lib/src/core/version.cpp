#include "glintscope/core/version.hpp"

namespace glintscope {

std::string version() { return GLINTSCOPE_VERSION; }

}  // namespace glintscope
