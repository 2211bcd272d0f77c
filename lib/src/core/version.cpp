#include "glintscope/version.hpp"

namespace glintscope {

std::string version() { return GLINTSCOPE_VERSION; }

}  // namespace glintscope
