// What the `strata` subcommands share: registration, progress and warning output, common options.
#pragma once

#include "strata/relief/texture_set.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace strata::cli {

// Each subcommand lives in cmd_<name>.cpp and registers itself on the app; its callback does the work
// and throws strata::Error on failure (main() maps the kind to the exit code).
void addPatternCommand(CLI::App& app);
void addImportCommand(CLI::App& app);
void addComposeCommand(CLI::App& app);
void addAoCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addDualDepthCommand(CLI::App& app);

// A progress line on stderr, only when stderr is a terminal (pipes and CI logs stay clean).
void progress(const std::string& message);
// "strata: warning: ..." / "strata: note: ..." on stderr, always.
void warn(const std::string& message);
void note(const std::string& message);

// --bit-depth 8|16 (default 16), shared by every command that writes a texture set.
void addBitDepthOption(CLI::App& command, int& bitDepth);

// Prints what was written ("wrote DIR: depth.png normal.png ...") on stdout.
void reportWritten(const std::filesystem::path& dir, const std::vector<std::filesystem::path>& files);

}  // namespace strata::cli
