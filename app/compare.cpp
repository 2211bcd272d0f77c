// glintscope compare A.exr B.exr [--fail-above X] [--diff D.png] [--json R.json]: two lobe or
// NDF EXRs written by glintscope, layer by layer (output/lobe_comparison.hpp). Exit status as
// cmp and diff: 0 alike (every relative L2 at most X), 1 above X, 2 on bad input.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "options.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/output/lobe_comparison.hpp"

namespace glintscope::cli {
namespace {

struct CompareSettings {
    std::string a;
    std::string b;
    double fail_above = -1.0;
    std::string diff;
    std::string json;
};

LobeFileComparison compare_and_write(const CompareSettings& settings) {
    if (!settings.diff.empty()) check_output_path(settings.diff, {"png"}, "--diff");
    if (!settings.json.empty()) check_output_path(settings.json, {"json"}, "--json");
    const LobeFileComparison comparison = compare_lobe_exrs(settings.a, settings.b);
    std::fputs(comparison_table(comparison).c_str(), stdout);
    if (!settings.json.empty()) write_text_file(settings.json, comparison_json(comparison));
    if (!settings.diff.empty()) write_comparison_figure(comparison, settings.diff);
    return comparison;
}

void run(const CompareSettings& settings) {
    LobeFileComparison comparison;
    try {
        comparison = compare_and_write(settings);
    } catch (const Error& e) {
        throw ExitStatus(e.what(), 2);
    }
    if (settings.fail_above < 0.0) return;
    for (std::size_t k = 0; k < comparison.layers.size(); ++k)
        if (comparison.layers[k].relative_l2 > settings.fail_above)
            throw ExitStatus("layer " + comparison.test.names[k] + ": relative L2 " +
                                 shortest_text(comparison.layers[k].relative_l2) + " exceeds --fail-above " +
                                 shortest_text(settings.fail_above),
                             1);
}

}  // namespace

void add_compare_command(CLI::App& app) {
    auto settings = std::make_shared<CompareSettings>();
    CLI::App* command = app.add_subcommand(
        "compare", "Compare two lobe or NDF EXRs layer by layer (relative L2, largest difference and where, energy "
                   "ratio, peak offset, log error); exit 0 alike, 1 above --fail-above, 2 on bad input");
    command->add_option("a", settings->a, "Image A (.exr written by lobe, ndf, fit or batch)")->required();
    command->add_option("b", settings->b, "Image B, the reference: relative L2 = |A - B| / |B| over the disk")->required();
    command->add_option("--fail-above", settings->fail_above,
                        "Exit 1 when any layer's relative L2 exceeds X (e.g. 0.01), after writing --json and --diff")
        ->check(kNonNegative)
        ->type_name("X");
    command->add_option("--diff", settings->diff,
                        "Picture (.png) of the layer of largest relative L2: A and B exposed alike, and A - B on a "
                        "diverging scale with its colour bar");
    command->add_option("--json", settings->json, "The numbers per layer and both inputs' method and query, as JSON");
    command->callback([settings] { run(*settings); });
}

}  // namespace glintscope::cli
