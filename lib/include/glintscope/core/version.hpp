#pragma once
#include <string>

namespace glintscope {

// The project version from CMake (project(glintscope VERSION ...)).
std::string version();

}  // namespace glintscope
