// glintscope batch MANIFEST.toml [--jobs N] [--shard I/N] [--force]: a comparison figure from a
// manifest, computing only the panels that are missing or out of date (docs/batch.md).
#include <cstdio>
#include <map>
#include <memory>

#include "commands.hpp"
#include "glintscope/batch/batch.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "progress.hpp"

namespace glintscope::cli {
namespace {

struct BatchSettings {
    std::string manifest;
    int jobs = 1;
    std::string shard;
    bool force = false;
};

// "I/N", 1 ≤ I ≤ N, as (I − 1, N).
std::pair<std::size_t, std::size_t> parse_shard(const std::string& text) {
    const std::vector<std::string> parts = split(text, '/');
    try {
        if (parts.size() != 2) throw Error("");
        const long long count = parse_integer(parts[1], 1, 100000);
        const long long index = parse_integer(parts[0], 1, count);
        return {std::size_t(index - 1), std::size_t(count)};
    } catch (const Error&) {
        throw Error("--shard must be I/N with 1 <= I <= N, got '" + text + "'");
    }
}

void run(const BatchSettings& settings) {
    BatchOptions options;
    if (!settings.shard.empty()) std::tie(options.shard_index, options.shard_count) = parse_shard(settings.shard);
    if (settings.jobs < 1 || settings.jobs > 256) throw Error("--jobs must be 1 to 256");
    options.jobs = settings.jobs;
    options.force = settings.force;
    const Manifest manifest = load_manifest(settings.manifest);
    const LobeOutputOptions output;
    BatchResult result;
    {
        ProgressBar progress("batch");
        result = run_batch(manifest, options, output, [&](std::size_t done, std::size_t total, const std::string& what) {
            progress.update(done, total, what);
        });
    }
    // Warnings per panel; each distinct note (e.g. the supersampling chosen) once, with its panels.
    std::map<std::string, std::vector<std::string>> notes;
    for (const PanelReport& panel : result.panels) {
        for (const std::string& warning : panel.warnings)
            std::fprintf(stderr, "glintscope: warning: %s: %s\n", panel.panel.c_str(), warning.c_str());
        for (const std::string& note : panel.notes) notes[note].push_back(panel.panel);
    }
    for (const auto& [note, panels] : notes)
        std::fprintf(stderr, "glintscope: note: %s (%zu panel%s)\n", note.c_str(), panels.size(), panels.size() == 1 ? "" : "s");
    std::printf("%zu panel%s computed, %zu up to date\n", result.computed, result.computed == 1 ? "" : "s",
                result.up_to_date);
    if (result.assembled)
        std::printf("figure: %s\nrecord: %s\n", result.figure_path.c_str(), result.record_path.c_str());
    else
        std::printf("shard %s done; run without --shard to assemble the figure\n", settings.shard.c_str());
}

}  // namespace

void add_batch_command(CLI::App& app) {
    auto settings = std::make_shared<BatchSettings>();
    CLI::App* command = app.add_subcommand("batch", "A comparison figure from a TOML manifest (docs/batch.md)");
    command->add_option("manifest", settings->manifest, "The manifest (.toml)")->required();
    command->add_option("--jobs", settings->jobs, "Panels computed at once")->capture_default_str();
    command->add_option("--shard", settings->shard,
                        "Compute only shard I of N (every N-th panel); a run without --shard assembles the figure")
        ->type_name("I/N");
    command->add_flag("--force", settings->force, "Recompute panels that are up to date");
    command->callback([settings] { run(*settings); });
}

}  // namespace glintscope::cli
