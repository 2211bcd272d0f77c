#pragma once
// Where data came from and what was done to it, as ordered key/value text: a heightfield's
// provenance, a lobe image's query and the method's choices. Written into every output
// (EXR header attributes, X3P record, JSON sidecars).
#include <map>
#include <string>

namespace glintscope {

using Provenance = std::map<std::string, std::string>;

}  // namespace glintscope
