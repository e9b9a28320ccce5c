// strata: the command-line tool. Thin: it parses, calls the library, and reports.
//
// Exit codes (docs/cli.md):
//   0 success, 1 command line (usage), 2 I/O (a file cannot be read or written),
//   3 invalid input (content is wrong: corrupt image, bad material key, negative weight),
//   4 runtime failure, 5 unsupported input (format variant, oversized image).
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/core/interrupt.h"
#include "strata/core/memory_budget.h"
#include "strata/core/version.h"

#include <iostream>
#include <new>

int main(int argc, char** argv) {
    // First, before any thread: SIGINT / SIGTERM / SIGHUP remove what was being written (docs/cli.md).
    strata::installInterruptCleanup();
    CLI::App app{
        "strata: relief textures, meta-relief composition, texture-space ambient occlusion and relief "
        "rendering"};
    app.set_version_flag("--version", std::string("strata ") + strata::kVersion);
    app.require_subcommand(1);
    // The memory budget (docs/cli.md): before the subcommand, e.g. `strata --max-memory 2G ao ...`.
    app.add_option_function<std::string>(
           "--max-memory",
           [](const std::string& text) { strata::setMemoryBudget(strata::parseMemorySize(text)); },
           "Refuse inputs and outputs that need more memory than SIZE (e.g. 512M, 4G); default half of "
           "physical memory")
        ->type_name("SIZE");
    app.footer(
        "Exit codes: 0 ok, 1 usage, 2 I/O, 3 invalid input, 4 runtime, 5 unsupported. See docs/cli.md.");
    strata::cli::addPatternCommand(app);
    strata::cli::addImportCommand(app);
    strata::cli::addComposeCommand(app);
    strata::cli::addAoCommand(app);
    strata::cli::addInfoCommand(app);
    strata::cli::addRenderCommand(app);
    strata::cli::addCompareCommand(app);
    strata::cli::addDualDepthCommand(app);
    strata::cli::addConeMapCommand(app);
    strata::cli::addMesoCommand(app);
    strata::cli::addExportCommand(app);
    strata::cli::addGdmCommand(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version are "errors" with exit code 0 to CLI11; everything else is usage, reported
        // like every other error.
        if (e.get_exit_code() == 0) return app.exit(e);
        std::cerr << "strata: error: " << e.what() << "\nRun with --help for more information.\n";
        return strata::exitCode(strata::ErrorKind::Usage);
    } catch (...) {
        return strata::reportCurrentException("strata");
    }
    return 0;
}
