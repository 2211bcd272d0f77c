#pragma once
// Every failure the library reports to a user is a glintscope::Error whose message is one
// line naming the problem (and the file or option involved); the CLI prints it and exits 1.
#include <stdexcept>
#include <string>

namespace glintscope {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace glintscope
