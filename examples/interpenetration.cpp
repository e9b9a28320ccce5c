// Interpenetration (relief-mapping paper Sec. 5, Fig. 18): a plain sphere pushed through a relief-mapped
// plane, with depth correction (gl_FragDepth of the relief point) and without it, side by side.
// Run: build/release/examples/example_interpenetration docs/img   -> docs/img/render_interpenetration.png
#include "strata/gl/context.h"
#include "strata/gl/gpu_material.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/gl/relief_renderer.h"
#include "strata/image/image_io.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/relief/patterns.h"

#include <glm/gtc/matrix_transform.hpp>

#include <filesystem>
#include <iostream>

int main(int argc, char** argv) {
    using namespace strata;
    if (argc != 2) {
        std::cerr << "usage: example_interpenetration OUTPUT_DIR\n";
        return 1;
    }
    try {
        const auto context = gl::HeadlessContext::create();
        gl::ReliefRenderer renderer;
        const gl::GpuMesh plane = gl::uploadMesh(makeBuiltinMesh("plane"));
        const gl::GpuMesh sphere = gl::uploadMesh(makeBuiltinMesh("sphere"));
        const ReliefTexture stones = makePattern("stone-bricks", {512, 1, 0.08});
        const gl::GpuMaterial material = gl::uploadMaterial(stones, stones.depthScale);

        gl::RenderRequest request;
        // Two spheres of radius 0.35 sunk to different depths: the relief's stones cut them where they stand.
        const glm::dmat4 a = glm::scale(glm::translate(glm::dmat4(1.0), {-0.35, 0.1, 0.02}), glm::dvec3(0.7));
        const glm::dmat4 b =
            glm::scale(glm::translate(glm::dmat4(1.0), {0.45, -0.15, -0.05}), glm::dvec3(0.7));
        request.objects.push_back({&plane, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
        request.objects.push_back({&sphere, a, nullptr, glm::dvec3(0.75, 0.3, 0.25)});
        request.objects.push_back({&sphere, b, nullptr, glm::dvec3(0.25, 0.45, 0.75)});
        request.camera.eye = {0.2, -1.6, 0.75};
        request.camera.target = {0.05, 0.0, 0.0};
        request.camera.fovYDegrees = 40.0;
        request.relief.tiling = 2.0;
        request.relief.depthScale = 0.12;
        request.lighting.lightPosition = {1.5, -1.0, 2.5};
        request.picture.width = 480;
        request.picture.height = 320;
        request.relief.depthCorrection = true;
        const Image with = renderer.render(request);
        request.relief.depthCorrection = false;
        const Image without = renderer.render(request);

        const int gap = 6;
        Image sheet(2 * with.width() + gap, with.height(), 3, 0.17f);
        for (int y = 0; y < with.height(); ++y)
            for (int x = 0; x < with.width(); ++x)
                for (int c = 0; c < 3; ++c) {
                    sheet.at(x, y, c) = with.at(x, y, c);
                    sheet.at(with.width() + gap + x, y, c) = without.at(x, y, c);
                }
        const std::filesystem::path out = std::filesystem::path(argv[1]) / "render_interpenetration.png";
        PngWriteOptions png;
        png.bitDepth = PngBitDepth::Eight;
        writePng(out, sheet, png);
        std::cout << "wrote " << out.string() << " (left: depth correction, right: without)\n";
    } catch (const std::exception& e) {
        std::cerr << "example_interpenetration: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
