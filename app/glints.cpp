// glintscope glints [HEIGHTFIELD] --outgoing THETA,PHI -o MAP.png: the discrete method's glint map,
// f_r for one pair of directions as the footprint moves over a grid of positions.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/maps/glint_map.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"
#include "options.hpp"
#include "progress.hpp"
#include "query_flags.hpp"

namespace glintscope::cli {
namespace {

struct GlintSettings {
    std::string heightfield = "builtin:isotropic";
    QueryText given;
    std::vector<double> outgoing_deg;
    int size = 128;
    double step_um = 1.0;
    std::string output;
};

void run_glints(const GlintSettings& settings) {
    check_output_path(settings.output, {"png"}, "-o");
    QueryText text = settings.given;
    text.emplace_back("heightfield", settings.heightfield);
    const LobeQuery query = make_query(text);
    const Vec3 omega_o = direction_from_spherical(degrees_to_radians(settings.outgoing_deg[0]),
                                                  degrees_to_radians(settings.outgoing_deg[1]));
    ScalarImage map;
    {
        ProgressBar bar("glints");
        map = discrete_glint_map(query, omega_o, settings.size, settings.step_um,
                                 [&bar](std::size_t done, std::size_t total) { bar.update(done, total, "rows"); });
    }
    const float peak = *std::max_element(map.values.begin(), map.values.end());
    double sum = 0.0;
    int lit = 0;
    for (float value : map.values) {
        sum += value;
        lit += value > 0.0f ? 1 : 0;
    }
    // The label says what the map is: its extent, the flakes, the footprint and both directions.
    const std::string side = shortest_text(settings.size * settings.step_um);
    const auto flakes = query.method_options.find("flakes");
    const Vec3 wi = query.omega_i;
    const double theta_i = std::acos(wi.z) * 180.0 / pi, phi_i = std::atan2(wi.y, wi.x) * 180.0 / pi;
    std::string label = "f_r [sr^-1] by footprint centre, " + side + " x " + side + " um; N = ";
    label.append(flakes != query.method_options.end() ? flakes->second : std::string("1e6"));
    const double width = box_width_um(query.footprint), height = box_height_um(query.footprint);
    label.append(query.footprint.shape != FootprintShape::box ? ", sigma_c " + shortest_text(query.footprint.sigma_um)
                 : width == height ? ", box " + shortest_text(width)
                                   : ", box " + shortest_text(width) + " x " + shortest_text(height));
    label.append(" um; in " + shortest_text(std::round(theta_i * 10) / 10) + "," + shortest_text(std::round(phi_i * 10) / 10) +
                 ", out " + shortest_text(settings.outgoing_deg[0]) + "," + shortest_text(settings.outgoing_deg[1]) + " deg");
    ColorLegend legend{0.0, std::max(static_cast<double>(peak), 1e-30), label, ColorMap::inferno};
    write_colormapped_png(settings.output, map, legend);
    std::printf("glint map %dx%d, spacing %s um: mean f_r %.6g, max %.6g sr^-1, %d of %d positions lit\n", settings.size,
                settings.size, shortest_text(settings.step_um).c_str(), sum / map.values.size(), peak, lit,
                static_cast<int>(map.values.size()));
}

}  // namespace

void add_glints_command(CLI::App& app) {
    auto settings = std::make_shared<GlintSettings>();
    CLI::App* command = app.add_subcommand(
        "glints", "Glint map of the discrete method: f_r [1/sr] for one incident and one outgoing direction as the "
                  "footprint moves over a grid of positions (map view, centred on --centre)");
    command->add_option("heightfield", settings->heightfield,
                        "Heightfield (read only by --distribution pndf; default builtin:isotropic)");
    command->add_option("--outgoing", settings->outgoing_deg, "Viewing direction THETA,PHI in degrees")
        ->delimiter(',')
        ->expected(2)
        ->required();
    command->add_option("--size", settings->size, "Positions along each side (1-4096)")->capture_default_str();
    add_length_option(*command, "--spacing", settings->step_um, "Distance between neighbouring positions (default 1um)");
    command->add_option("-o,--output", settings->output, "Output picture (.png)")->required()->type_name("PNG");
    add_query_flags(*command, settings->given, Quantity::brdf,
                    {"res", "supersample", "quantity", "model", "spectral"});
    add_method_option_flags(*command, settings->given, Quantity::brdf);
    command->callback([settings] { run_glints(*settings); });
}

}  // namespace glintscope::cli
