// strata pattern --list
// strata pattern NAME [--size N] [--seed K] [--depth-scale S] [--bit-depth 8|16] [--format png|exr]
// [--write-height] -o DIR
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/relief/patterns.h"
#include "strata/relief/relief_texture.h"

#include <nlohmann/json.hpp>

#include <iomanip>
#include <iostream>
#include <memory>

namespace strata::cli {

namespace {

struct PatternOptions {
    bool list = false;
    std::string name;
    PatternParams params;
    SetOutputOptions setOutput;
    std::filesystem::path output;
};

void runPattern(const PatternOptions& options) {
    if (options.list) {
        for (const auto& info : patternList())
            std::cout << std::left << std::setw(14) << info.name << info.description << "\n";
        return;
    }
    if (options.name.empty())
        throw Error(ErrorKind::Usage, "pattern: give a pattern NAME (see `strata pattern --list`)");
    if (options.output.empty())
        throw Error(ErrorKind::Usage, "pattern: give the output directory with -o DIR");
    progress("generating " + options.name + " at " + std::to_string(options.params.size) + "^2");
    const ReliefTexture texture = makePattern(options.name, options.params);
    TextureSetWriteOptions write;
    applySetOutputOptions(options.setOutput, write);
    write.normalSource = "derived";
    write.sourceJson = nlohmann::json{{"kind", "pattern"},
                                      {"pattern", options.name},
                                      {"size", options.params.size},
                                      {"seed", options.params.seed},
                                      {"depth_scale", options.params.depthScale}}
                           .dump();
    reportWritten(options.output, writeTextureSet(options.output, texture, write));
}

}  // namespace

void addPatternCommand(CLI::App& app) {
    auto options = std::make_shared<PatternOptions>();
    CLI::App* command = app.add_subcommand("pattern", "Write a built-in procedural relief texture set");
    command->add_flag("--list", options->list, "List the built-in patterns and exit");
    command->add_option("name", options->name, "Pattern name (see --list)");
    command->add_option("--size", options->params.size, "Width = height in texels")
        ->check(CLI::Range(kMinPatternSize, kMaxPatternSize))
        ->capture_default_str();
    command->add_option("--seed", options->params.seed, "Random seed")->capture_default_str();
    command
        ->add_option("--depth-scale", options->params.depthScale,
                     "Depth scale S for the normal map (depth of d = 1 in tile widths), (0, 10]")
        ->check(depthScaleRange())
        ->capture_default_str();
    addSetOutputOptions(*command, options->setOutput);
    command->add_option("-o,--output", options->output, "Output directory");
    command->callback([options] { runPattern(*options); });
}

}  // namespace strata::cli
