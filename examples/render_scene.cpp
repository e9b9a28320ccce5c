// A scene rendered from your own program, with the calls `strata render` makes (docs/scenes.md, "A scene in
// your own program"): read the scene, prepare its material on the CPU, upload, render, write.
// Run: build/release/examples/example_render_scene examples/scenes/sphere_bricks.json out/sphere.png
#include "strata/core/error.h"
#include "strata/gl/context.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/gl/relief_renderer.h"
#include "strata/gl/scene_material.h"
#include "strata/image/image_io.h"
#include "strata/scene/scene_material.h"

#include <iostream>

int main(int argc, char** argv) {
    using namespace strata;
    if (argc != 3) {
        std::cerr << "usage: example_render_scene SCENE.json OUTPUT.png\n";
        return 1;
    }
    try {
        const Scene scene = readScene(argv[1]);
        const auto context = gl::HeadlessContext::create();
        const Mesh mesh = loadSceneMesh(scene);
        const SceneMaterial material = prepareSceneMaterial(scene);
        const gl::GpuMesh gpuMesh = gl::uploadMesh(mesh);
        const gl::GpuMaterial gpuMaterial = gl::uploadSceneMaterial(material);

        gl::RenderRequest request;
        request.objects.push_back({&gpuMesh, glm::dmat4(1.0), &gpuMaterial, glm::dvec3(0.8)});
        request.relief = scene.relief;
        request.relief.depthScale = material.depthScale;
        request.lighting = scene.lighting;
        request.picture = scene.picture;
        const double aspect = static_cast<double>(scene.picture.width) / scene.picture.height;
        request.camera = scene.camera.value_or(frameCamera(meshBounds(mesh), aspect));
        // Shaded pictures as the CLI writes them: 8-bit, dithered (CONVENTIONS §5).
        writePng(argv[2], gl::ReliefRenderer().render(request), {PngBitDepth::Eight, true});
        std::cout << argv[2] << ": " << toString(material.kind) << " material, S = " << material.depthScale
                  << "\n";
    } catch (...) {
        return reportCurrentException("example_render_scene");
    }
    return 0;
}
