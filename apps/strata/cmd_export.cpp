// strata export SET --preset gltf|unity-hdrp|unreal|godot|strata -o DIR [--normal-y up|down]
//                   [--format png|exr] [--roughness R] [--metallic M] [--mesh NAME|FILE] [--name NAME]
// SET: a texture-set directory or its strata.json. Writes DIR in the preset's layout (docs/export.md).
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/mesh/mesh_loader.h"
#include "strata/relief/export.h"

#include <memory>

namespace fs = std::filesystem;

namespace strata::cli {

namespace {

struct ExportCommandOptions {
    fs::path input;
    fs::path output;
    std::string preset;
    std::string normalY;
    std::string format = "png";
    double roughness = 0.8;
    double metallic = 0.0;
    std::string mesh;
    std::string name = "relief";
};

void runExport(const ExportCommandOptions& o) {
    // Every flag is checked before any file is read.
    ExportOptions options;
    options.preset = parseExportPreset(o.preset);
    if (!o.normalY.empty()) options.normalY = parseNormalY(o.normalY);
    options.format = parseExportFormat(o.format);
    options.roughness = o.roughness;
    options.metallic = o.metallic;
    options.assetName = o.name;
    if (!o.mesh.empty() && options.preset != ExportPreset::Gltf)
        throw Error(ErrorKind::Usage, "--mesh: only the gltf preset writes a mesh, not " + o.preset);
    if (o.name.empty() || o.name.find('/') != std::string::npos)
        throw Error(ErrorKind::Usage, "--name: expected a file name without '/', got '" + o.name + "'");
    checkExportOptions(options);

    const fs::path dir = fs::is_directory(o.input) ? o.input : o.input.parent_path();
    options.inputs = {dir / kSidecarName};
    if (!o.mesh.empty()) {
        progress("mesh " + o.mesh);
        // As `strata render --mesh`: an existing file is loaded, anything else is a built-in's name.
        if (fs::exists(o.mesh)) {
            options.mesh = loadMesh(o.mesh);
            options.inputs.emplace_back(o.mesh);
        } else {
            options.mesh = makeBuiltinMesh(o.mesh);
        }
    }
    progress("reading " + o.input.string());
    const nlohmann::json sidecar = readSidecar(o.input);
    for (const char* key : {"depth", "normal", "color", "ao", "packed"})
        if (sidecar.contains(key) && sidecar[key].is_object() && sidecar[key].contains("file"))
            options.inputs.push_back(dir / sidecar[key]["file"].get<std::string>());
    options.sourceSidecar = sidecar.dump();
    const ReliefTexture texture = readTextureSet(o.input);
    progress("exporting " + o.preset + " to " + o.output.string());
    reportWritten(o.output, exportTextureSet(o.output, texture, options));
}

}  // namespace

void addExportCommand(CLI::App& app) {
    auto options = std::make_shared<ExportCommandOptions>();
    CLI::App* command = app.add_subcommand(
        "export", "Write a texture set in the layout a game engine reads (glTF, Unity HDRP, Unreal, Godot)");
    command->add_option("SET", options->input, "Texture-set directory or its strata.json")->required();
    command->add_option("--preset", options->preset, "gltf | unity-hdrp | unreal | godot | strata")
        ->required();
    command->add_option("-o,--output", options->output, "Output directory")->required();
    command->add_option("--normal-y", options->normalY,
                        "Normal map convention: up (OpenGL) or down (DirectX); default: the engine's");
    command->add_option("--format", options->format, "png | exr (exr: the strata preset only)")
        ->capture_default_str();
    command->add_option("--roughness", options->roughness, "Constant roughness, [0, 1]")
        ->capture_default_str();
    command->add_option("--metallic", options->metallic, "Constant metallic, [0, 1]")->capture_default_str();
    command->add_option("--mesh", options->mesh,
                        "gltf: a built-in mesh (teapot, cube, sphere, torus, cylinder, vase, patch, trunk, "
                        "plane, quad) or a mesh file (.obj, .gltf, .glb); default: the unit quad");
    command->add_option("--name", options->name, "gltf: the asset's file name, NAME.gltf and NAME.bin")
        ->capture_default_str();
    command->callback([options] { runExport(*options); });
}

}  // namespace strata::cli
