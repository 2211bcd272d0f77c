#pragma once
// What `lobe` and `ndf` share: query flags generated from the library's query keys and method
// options, output flags, and the run (check outputs, build the query, warn, compute, write,
// summarise). Each command is then a few lines (lobe.cpp, ndf.cpp).
#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "glintscope/lobe/image.hpp"

namespace glintscope::cli {

struct ImageCommandSettings;

// Adds the heightfield argument, every query key as a flag, --method, --option, method-option
// flags, --from, and the output flags to `command`, and runs the command on callback.
void add_image_command(CLI::App& command, Quantity quantity, const std::string& default_method);

}  // namespace glintscope::cli
