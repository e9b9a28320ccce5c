// strata dual-depth --mesh MESH|FILE [--axis x|y|z] [--size N] [--tessellation N] -o DIR
// Samples a closed mesh into a dual-depth relief texture (docs/dual-depth.md).
#include "cli_common.h"

#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/image/image.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/mesh/mesh_loader.h"
#include "strata/relief/dual_depth.h"

#include <memory>

namespace fs = std::filesystem;

namespace strata::cli {

namespace {

struct DualDepthOptions {
    std::string mesh;
    std::string axis = "z";
    int size = 256;
    int tessellation = 0;  // 0: the built-in's default
    fs::path output;
};

void runDualDepth(const DualDepthOptions& options) {
    const Axis axis = parseAxis(options.axis);
    // A path that exists, or anything that looks like a file name, is a file (so that a missing file is an
    // I/O error, not an unknown built-in); a bare word is a built-in.
    const fs::path asFile(options.mesh);
    std::error_code ec;
    const bool isFile = fs::exists(asFile, ec) || asFile.has_extension() || asFile.has_parent_path();
    Mesh mesh;
    std::vector<fs::path> inputs;
    progress("mesh " + options.mesh);
    if (isFile) {
        MeshLoadOptions load;
        load.requireUvs = false;  // sampling needs positions and normals only (an OFF bunny has no uvs)
        mesh = loadMesh(asFile, load);
        inputs.push_back(asFile);
    } else {
        BuiltinMeshParams params;
        if (options.tessellation > 0) params.tessellation = options.tessellation;
        mesh = makeBuiltinMesh(options.mesh, params);
    }
    for (const char* name : {"packed.png", "strata.json"})
        refuseToOverwriteInputs(options.output / name, inputs);
    progress("sampling " + std::to_string(options.size) + "x" + std::to_string(options.size) + " along " +
             toString(axis));
    const DualDepthTexture texture = makeDualDepth(mesh, axis, options.size);
    reportWritten(options.output, writeDualDepth(options.output, texture, options.mesh));
}

}  // namespace

void addDualDepthCommand(CLI::App& app) {
    auto options = std::make_shared<DualDepthOptions>();
    CLI::App* command = app.add_subcommand(
        "dual-depth",
        "Sample a closed mesh into a dual-depth relief texture (front and back depth, normals)");
    command
        ->add_option(
            "--mesh", options->mesh,
            "Built-in mesh (teapot, cube, sphere, torus, cylinder) or a mesh file (.obj, .gltf, .glb, "
            ".off; uvs not needed)")
        ->required();
    command->add_option("--axis", options->axis, "Sampling axis, seen from its + side (default z)")
        ->check(CLI::IsMember({"x", "y", "z"}));
    command->add_option("--size", options->size, "Texels per side, 1..16384 (default 256)")
        ->check(CLI::Range(1, Image::kMaxDimension));
    command->add_option("--tessellation", options->tessellation, "Tessellation of a built-in mesh, 1..256")
        ->check(CLI::Range(1, 256));
    command->add_option("-o,--output", options->output, "Output directory (packed.png, strata.json)")
        ->required();
    command->callback([options] { runDualDepth(*options); });
}

}  // namespace strata::cli
