#pragma once
// Command-line flags generated from the library's query keys and method table, so that every
// command that takes a query (lobe, ndf, validate) spells and documents it the same way.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "glintscope/lobe/image.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/lobe/query_keys.hpp"

namespace glintscope::cli {

// "--sigma-c" for the key "sigma_c".
std::string flag_name(const std::string& key);

// One flag per query key except the heightfield (a positional argument) and `skip`; each given
// flag appends (key, value) to `given`, in command-line order.
void add_query_flags(CLI::App& command, QueryText& given, Quantity quantity, const std::vector<std::string>& skip);

// One flag per method option key of the methods answering `quantity` (help names the methods
// that read it), and --option KEY=VALUE; each appends ("option.KEY", value) to `given`. A
// nonempty `only` limits the flags to those methods' options.
void add_method_option_flags(CLI::App& command, QueryText& given, Quantity quantity,
                             const std::vector<std::string>& only = {});

}  // namespace glintscope::cli
