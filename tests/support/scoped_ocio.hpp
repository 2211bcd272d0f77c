#pragma once
// Sets or clears $OCIO (the OpenColorIO config the colour code falls back to) for the lifetime
// of the object and restores the previous value afterwards.
#include <cstdlib>
#include <optional>
#include <string>

namespace glintscope::testing {

class ScopedOcio {
public:
    explicit ScopedOcio(const std::optional<std::string>& value) {
        if (const char* old = std::getenv("OCIO")) previous_ = old;
        if (value) ::setenv("OCIO", value->c_str(), 1);
        else ::unsetenv("OCIO");
    }
    ~ScopedOcio() {
        if (previous_) ::setenv("OCIO", previous_->c_str(), 1);
        else ::unsetenv("OCIO");
    }
    ScopedOcio(const ScopedOcio&) = delete;
    ScopedOcio& operator=(const ScopedOcio&) = delete;

private:
    std::optional<std::string> previous_;
};

}  // namespace glintscope::testing
