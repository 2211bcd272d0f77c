// glintscope lobe HEIGHTFIELD -o OUT.exr: a reflection lobe f_r(ω_i, ω_o) over the projected
// hemisphere of ω_o for one footprint and one incident direction, by any method that answers
// the brdf quantity (default fft: exact and the fastest for whole images).
#include "commands.hpp"
#include "image_command.hpp"

namespace glintscope::cli {

void add_lobe_command(CLI::App& app) {
    CLI::App* command = app.add_subcommand(
        "lobe", "Reflection lobe f_r(omega_i, omega_o) [1/sr] over the projected hemisphere of one footprint");
    add_image_command(*command, Quantity::brdf, "fft");
}

}  // namespace glintscope::cli
