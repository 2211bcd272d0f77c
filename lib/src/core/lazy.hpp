#pragma once
// A value made on its first use and then read by every thread (std::call_once): what a BSDF needs
// only to sample, such as a footprint's sampling table, which a caller that only evaluates (a
// renderer's light sample) never pays for. If making it throws, the next use tries again.
#include <functional>
#include <mutex>
#include <optional>
#include <utility>

namespace glintscope {

template <class T>
class Lazy {
public:
    explicit Lazy(std::function<T()> make) : make_(std::move(make)) {}

    const T& get() const {
        std::call_once(once_, [this] { value_.emplace(make_()); });
        return *value_;
    }

private:
    std::function<T()> make_;
    mutable std::once_flag once_;
    mutable std::optional<T> value_;
};

}  // namespace glintscope
