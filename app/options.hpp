#pragma once
// Option helpers shared by the subcommands, so every length takes the same unit suffixes and
// every heightfield input takes the same loading options.
#include <CLI/CLI.hpp>
#include <string>

#include "glintscope/io/heightfield_io.hpp"

namespace glintscope::cli {

// A length option ("0.5um", "500nm", "2mm"; bare numbers are µm) stored in µm.
CLI::Option* add_length_option(CLI::App& command, const std::string& name, double& target_um,
                               const std::string& description);

// A check that a number is finite and not negative, whose message says so in those words (CLI11's
// NonNegativeNumber prints its range up to the largest double).
extern const CLI::Validator kNonNegative;

// The loading options of every heightfield input: --channel, --height-unit, --texel,
// --height-scale, --periodic (see LoadOptions).
void add_load_options(CLI::App& command, LoadOptions& options);

// A heightfield argument: a file read with `options`, or builtin:KIND generated from the
// default recipe of KIND (see generate.hpp).
Heightfield load_heightfield_argument(const std::string& argument, const LoadOptions& options);

}  // namespace glintscope::cli
