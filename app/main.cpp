// glintscope: how a surface's microgeometry reflects light.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>
#include <exception>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "options.hpp"
#include "progress.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/version.hpp"

namespace {

// Edit distance, for suggesting the command a typo meant.
std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

// The first word that is not an option must be a command; if it is not, the usage error says
// which one is closest.
std::string unknown_command(const CLI::App& app, int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string word = argv[i];
        if (word.starts_with("-")) {
            if (word == "--threads") ++i;  // its value (--threads=N is one word)
            continue;
        }
        std::string closest;
        std::size_t best = SIZE_MAX;
        for (const CLI::App* command : app.get_subcommands({})) {
            if (command->get_name() == word) return "";
            const std::size_t distance = edit_distance(word, command->get_name());
            if (distance < best) best = distance, closest = command->get_name();
        }
        return "unknown command '" + word + "'" + (best <= 2 ? " (did you mean '" + closest + "'?)" : " (see --help)");
    }
    return "";
}

// For a long option the chosen command does not know, the closest one it does ("" if none is
// within two edits): a mistyped --lamda gets "did you mean '--lambda'?".
std::string option_suggestion(const CLI::App& app, int argc, char** argv) {
    std::vector<std::string> names;
    std::vector<const CLI::App*> scopes = {&app};
    for (const CLI::App* command : app.get_subcommands()) scopes.push_back(command);
    for (const CLI::App* scope : scopes)
        for (const CLI::Option* option : scope->get_options())
            for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    for (int i = 1; i < argc; ++i) {
        const std::string word = std::string(argv[i]).substr(0, std::string(argv[i]).find('='));
        if (!word.starts_with("--") || std::find(names.begin(), names.end(), word) != names.end()) continue;
        std::string closest;
        std::size_t best = SIZE_MAX;
        for (const std::string& name : names)
            if (const std::size_t distance = edit_distance(word, name); distance < best) best = distance, closest = name;
        if (best <= 2) return "did you mean '" + closest + "' for '" + word + "'?";
    }
    return "";
}

}  // namespace

namespace glintscope::cli {
std::string& invocation() {
    static std::string line;
    return line;
}
}  // namespace glintscope::cli

int main(int argc, char** argv) {
    for (int i = 0; i < argc; ++i) glintscope::cli::invocation() += (i ? " " : "") + std::string(i ? argv[i] : "glintscope");
    CLI::App app{"glintscope: heightfields, their reflection lobes and normal distributions.\n"
                 "Lengths are micrometres unless suffixed (0.5um, 500nm, 2mm); angles are degrees.",
                 "glintscope"};
    app.require_subcommand(1);
    // Usage errors are one line like every other error; exit status 2 marks them.
    app.failure_message([](const CLI::App*, const CLI::Error& e) {
        return std::string("glintscope: error: ") + e.what() + " (see --help)\n";
    });
    app.set_version_flag("--version", "glintscope " + glintscope::version());
    // Subcommands pass options they do not know (--threads) up to the main command.
    app.fallthrough();
    // The subcommands run on this thread, inside this scope (the library's count is per thread).
    std::optional<glintscope::ThreadScope> threads_scope;
    app.add_option_function<int>("--threads", [&](int threads) { threads_scope.emplace(threads); },
                                 "Worker threads (default: all cores; results do not depend on it)")
        ->check(glintscope::cli::kNonNegative)
        ->trigger_on_parse();

    app.add_flag_function("--quiet", [](std::int64_t) { glintscope::cli::verbosity().quiet = true; },
                          "No progress lines");
    app.add_flag_function("--verbose", [](std::int64_t) { glintscope::cli::verbosity().verbose = true; },
                          "Explain automatic choices (grids, kernel density, exposure)");

    glintscope::cli::add_generate_command(app);
    glintscope::cli::add_info_command(app);
    glintscope::cli::add_convert_command(app);
    glintscope::cli::add_preview_command(app);
    glintscope::cli::add_lobe_command(app);
    glintscope::cli::add_ndf_command(app);
    glintscope::cli::add_validate_command(app);
    glintscope::cli::add_batch_command(app);
    glintscope::cli::add_fit_command(app);
    glintscope::cli::add_glints_command(app);
    glintscope::cli::add_compare_command(app);
    glintscope::cli::add_render_command(app);

    if (const std::string problem = unknown_command(app, argc, argv); !problem.empty()) {
        std::fprintf(stderr, "glintscope: error: %s\n", problem.c_str());
        return 2;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ExtrasError& e) {
        const std::string suggestion = option_suggestion(app, argc, argv);
        if (suggestion.empty()) return app.exit(e) == 0 ? 0 : 2;
        std::fprintf(stderr, "glintscope: error: %s (%s)\n", e.what(), suggestion.c_str());
        return 2;
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    } catch (const glintscope::cli::ExitStatus& e) {
        std::fprintf(stderr, "glintscope: error: %s\n", e.what());
        return e.status;
    } catch (const glintscope::Error& e) {
        std::fprintf(stderr, "glintscope: error: %s\n", e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "glintscope: error: out of memory (is the requested size too large?)\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glintscope: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
