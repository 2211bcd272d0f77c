#pragma once
// One subcommand per file; each adds itself to the CLI and calls into the library.
#include <CLI/CLI.hpp>
#include <stdexcept>
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
void add_compare_command(CLI::App& app);
void add_render_command(CLI::App& app);

// A failure with its own exit status, printed like any error: compare exits 1 when the images
// differ beyond --fail-above and 2 on bad input, as cmp and diff do, so that scripts tell the two
// apart (other commands exit 1 on any error and 2 on a usage error).
class ExitStatus : public std::runtime_error {
public:
    ExitStatus(const std::string& message, int status) : std::runtime_error(message), status(status) {}
    int status;
};

}  // namespace glintscope::cli
