// glintscope ndf HEIGHTFIELD -o OUT.exr: a normal distribution D(h) over the projected disk of
// normals for one footprint, by any method that answers the ndf quantity.
#include "commands.hpp"
#include "image_command.hpp"

namespace glintscope::cli {

void add_ndf_command(CLI::App& app) {
    CLI::App* command = app.add_subcommand(
        "ndf", "Normal distribution D(h) over the projected disk of normals of one footprint (sum D (2/N)^2 = 1)");
    add_image_command(*command, Quantity::ndf, "pndf");
}

}  // namespace glintscope::cli
