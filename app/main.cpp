// glintscope: how a surface's microgeometry reflects light.
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "progress.hpp"
#include "glintscope/error.hpp"
#include "glintscope/parallel.hpp"
#include "glintscope/version.hpp"

int main(int argc, char** argv) {
    CLI::App app{"glintscope: heightfields, their reflection lobes and normal distributions.\n"
                 "Lengths are micrometres unless suffixed (0.5um, 500nm, 2mm); angles are degrees."};
    app.require_subcommand(1);
    // Usage errors are one line like every other error; exit status 2 marks them.
    app.failure_message([](const CLI::App*, const CLI::Error& e) {
        return std::string("glintscope: error: ") + e.what() + " (see --help)\n";
    });
    app.set_version_flag("--version", "glintscope " + glintscope::version());
    // Subcommands pass options they do not know (--threads) up to the main command.
    app.fallthrough();
    app.add_option_function<int>("--threads", [](int threads) { glintscope::set_thread_count(threads); },
                                 "Worker threads (default: all cores; results do not depend on it)")
        ->check(CLI::NonNegativeNumber)
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
    glintscope::cli::add_validate_command(app);
    glintscope::cli::add_batch_command(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
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
