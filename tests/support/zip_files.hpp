#pragma once
// Hand-made zip archives (X3P variants and hostile X3P files) for the tests.
#include <string>
#include <utility>
#include <vector>

namespace glintscope::testing {

// Writes an archive of the given members (name, contents); false if libzip fails.
bool write_zip(const std::string& path, const std::vector<std::pair<std::string, std::string>>& members);

// One member's contents, or "" when the archive or the member is missing.
std::string read_zip_member(const std::string& path, const std::string& name);

}  // namespace glintscope::testing
