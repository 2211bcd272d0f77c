#pragma once
// One subcommand per file; each adds itself to the CLI and calls into the library.
#include <CLI/CLI.hpp>
#include <string>

namespace glintscope::cli {

// The command line as typed, recorded in every output's metadata ("command_line").
std::string& invocation();

void add_generate_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_convert_command(CLI::App& app);
void add_preview_command(CLI::App& app);
void add_lobe_command(CLI::App& app);
void add_ndf_command(CLI::App& app);
void add_validate_command(CLI::App& app);
void add_batch_command(CLI::App& app);
void add_fit_command(CLI::App& app);
void add_glints_command(CLI::App& app);

}  // namespace glintscope::cli
