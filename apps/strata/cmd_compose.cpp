// strata compose MATERIAL.json -o DIR [--resolution N] [--normals paper|consistent]
//                [--ao exact|multiply|min|none] [--ao-method sweep|paper|brute] [--bit-depth 8|16] [--format
//                png|exr] [--write-height]
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/scene/material.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <optional>

namespace fs = std::filesystem;

namespace strata::cli {

namespace {

struct ComposeOptions {
    fs::path material;
    fs::path output;
    int resolution = 0;
    std::string normals;
    std::string ao;
    std::string aoMethod;
    SetOutputOptions setOutput;
};

void runCompose(const ComposeOptions& options) {
    // Everything is parsed, read and composed before anything is written: a rejected material
    // leaves no output at all.
    Material material = readMaterial(options.material);
    if (options.resolution > 0) material.compose.resolution = options.resolution;
    if (!options.normals.empty()) material.compose.normals = parseNormalMode(options.normals);
    if (options.ao == "none")
        material.ao.reset();
    else if (!options.ao.empty())
        material.ao = parseMetaAoMode(options.ao);
    if (!options.aoMethod.empty()) material.aoParams.method = parseAoMethod(options.aoMethod);

    progress("loading " + std::to_string(material.layers.size()) + " layers");
    std::vector<std::string> notes;
    const std::vector<CompositionLayer> layers =
        loadLayers(material, &notes, [](const std::string& message) { progress("  " + message); });
    for (const auto& text : notes) note(text);

    progress("composing");
    Composition composition = compose(layers, material.compose);
    for (const auto& text : composition.warnings) warn(text);

    std::optional<AoRecord> aoRecord;
    nlohmann::json aoSource = "none";
    if (material.ao) {
        const MetaAoMode mode = *material.ao;
        const AoParams& aoParams = material.aoParams;
        progress(std::string("ambient occlusion (") + toString(mode) + ", " + toString(aoParams.method) +
                 ")");
        composition.texture.ao =
            metaReliefAo(layers, material.compose, composition, mode, aoParams,
                         [](const std::string& message) { progress("  ambient occlusion of " + message); });
        aoRecord = AoRecord{};
        aoRecord->radius = aoParams.radius;
        aoRecord->method = metaReliefAoMethodName(mode, aoParams.method);
        aoRecord->directions = aoParams.directions;
        aoSource = {{"mode", toString(mode)},
                    {"method", toString(aoParams.method)},
                    {"radius", aoParams.radius},
                    {"directions", aoParams.directions},
                    {"depth_scale", material.compose.depthScale}};
        if (mode != MetaAoMode::Exact) {
            // What each layer was baked with (meta_relief_ao.h derives S_i and R_i).
            const auto perLayer = metaReliefLayerAoParams(layers, material.compose, aoParams);
            for (const auto& layerParams : perLayer)
                aoSource["layers"].push_back(layerParams
                                                 ? nlohmann::json{{"depth_scale", layerParams->depthScale},
                                                                  {"radius", layerParams->radius}}
                                                 : nlohmann::json("skipped: weight_depth 0, AO 1"));
        }
    }

    nlohmann::json source{{"kind", "meta-relief"},
                          {"material", options.material.string()},
                          {"normals", toString(material.compose.normals)},
                          {"color_from", material.compose.colorFrom},
                          {"ao", aoSource}};
    for (std::size_t i = 0; i < material.layers.size(); ++i) {
        const MaterialLayer& spec = material.layers[i];
        nlohmann::json layer{{"tiling", spec.tiling},
                             {"weight_depth", spec.weightDepth},
                             {"weight_normal", spec.weightNormal}};
        if (spec.pattern) {
            layer["pattern"] = *spec.pattern;
            layer["size"] = spec.patternParams.size;
            layer["seed"] = spec.patternParams.seed;
            layer["depth_scale"] = spec.patternParams.depthScale;
        } else {
            layer["file"] = (spec.depthFile ? *spec.depthFile : *spec.heightFile).string();
        }
        source["layers"].push_back(layer);
    }

    TextureSetWriteOptions write;
    applySetOutputOptions(options.setOutput, write);
    write.normalSource = toString(material.compose.normals);
    write.sourceJson = source.dump();
    write.inputs = materialInputs(material);
    write.ao = aoRecord;
    reportWritten(options.output, writeTextureSet(options.output, composition.texture, write));
}

}  // namespace

void addComposeCommand(CLI::App& app) {
    auto options = std::make_shared<ComposeOptions>();
    CLI::App* command =
        app.add_subcommand("compose", "Compose a meta-relief material (JSON) into a texture set");
    command->add_option("material", options->material, "Material file (docs/material.md)")->required();
    command->add_option("-o,--output", options->output, "Output directory")->required();
    command->add_option("--resolution", options->resolution, "Override the material's output resolution")
        ->check(CLI::Range(1, Image::kMaxDimension));
    command
        ->add_option("--normals", options->normals, "Override the normal mode: paper (Eq. 1) or consistent")
        ->check(CLI::IsMember({"paper", "consistent"}));
    command
        ->add_option("--ao", options->ao,
                     "Override the material's AO: exact (the composed depth's own AO), multiply or min "
                     "(the paper's per-layer combination), none (no AO map, packed B = 1)")
        ->check(CLI::IsMember({"exact", "multiply", "min", "none"}));
    command->add_option("--ao-method", options->aoMethod, "Override the material's AO method")
        ->check(CLI::IsMember({"sweep", "paper", "brute"}));
    addSetOutputOptions(*command, options->setOutput);
    command->callback([options] { runCompose(*options); });
}

}  // namespace strata::cli
