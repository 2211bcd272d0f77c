#pragma once
// MD5 (RFC 1321), for the checksums ISO 25178-72 puts in X3P files. Not for security.
#include <cstddef>
#include <string>

namespace glintscope {

// The digest of `size` bytes as 32 lower-case hexadecimal digits.
std::string md5_hex(const void* data, std::size_t size);

}  // namespace glintscope
