// Makes the pictures and numbers of docs/composition.md with the library alone:
//  - for each example material (Shaped Fabric, Shaped Metal, the 3-layer one), a strip
//    depth | normal (paper) | colour, composed at 512^2;
//  - for Shaped Fabric and the 3-layer material, the two normal modes side by side with the angle
//    between them as a heat map (black 0 deg, white >= 20 deg), and the mean and largest angle.
// Usage: example_composition_figures [EXAMPLES_DIR] [OUTPUT_DIR]   (defaults: examples docs/img)
#include "strata/image/image_io.h"
#include "strata/scene/material.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace strata;

namespace {

// Places images side by side (3-channel output; 1-channel images become gray), with a gap.
Image strip(const std::vector<Image>& images, int gap = 8) {
    int width = gap;
    int height = 0;
    for (const Image& image : images) {
        width += image.width() + gap;
        height = std::max(height, image.height());
    }
    Image out(width, height + 2 * gap, 3, 1.0f);
    int left = gap;
    for (const Image& image : images) {
        for (int y = 0; y < image.height(); ++y)
            for (int x = 0; x < image.width(); ++x)
                for (int c = 0; c < 3; ++c)
                    out.at(left + x, gap + y, c) = image.at(x, y, image.channels() == 1 ? 0 : c);
        left += image.width() + gap;
    }
    return out;
}

Image angleMap(const Image& a, const Image& b, double fullScaleDegrees) {
    Image out(a.width(), a.height(), 1);
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            double dot = 0.0;
            for (int c = 0; c < 3; ++c)
                dot += static_cast<double>(a.at(x, y, c)) * static_cast<double>(b.at(x, y, c));
            const double degrees = std::acos(std::clamp(dot, -1.0, 1.0)) * 180.0 / std::numbers::pi;
            out.at(x, y) = static_cast<float>(std::min(1.0, degrees / fullScaleDegrees));
        }
    return out;
}

// The region around a tile corner of the image repeated 2 x 2: a bake that does not tile shows a
// cross there.
Image cornerCrop(const Image& image, int half) {
    Image out(2 * half, 2 * half, image.channels());
    for (int y = 0; y < 2 * half; ++y)
        for (int x = 0; x < 2 * half; ++x)
            for (int c = 0; c < image.channels(); ++c)
                out.at(x, y, c) = image.atWrapped(image.width() - half + x, image.height() - half + y, c);
    return out;
}

Composition composeMaterial(const fs::path& file, NormalMode mode, int resolution) {
    Material material = readMaterial(file);
    material.compose.normals = mode;
    material.compose.resolution = resolution;
    return compose(loadLayers(material), material.compose);
}

}  // namespace

int main(int argc, char** argv) {
    const fs::path examples = argc > 1 ? argv[1] : "examples";
    const fs::path output = argc > 2 ? argv[2] : "docs/img";
    const int size = 512;
    try {
        for (const char* name : {"shaped_fabric", "shaped_metal", "three_layers"}) {
            const Composition paper =
                composeMaterial(examples / (std::string(name) + ".json"), NormalMode::Paper, size);
            writePng(output / ("compose_" + std::string(name) + ".png"),
                     strip({paper.texture.depth, encodeNormals(paper.texture.normal), paper.texture.color}),
                     {PngBitDepth::Eight, true});
        }
        // Seams: integer tilings (Shaped Fabric) against fractional ones (3 layers), around the tile corner.
        const Composition integer = composeMaterial(examples / "shaped_fabric.json", NormalMode::Paper, size);
        const Composition fractional =
            composeMaterial(examples / "three_layers.json", NormalMode::Paper, size);
        writePng(output / "compose_seams.png",
                 strip({cornerCrop(integer.texture.color, 128), cornerCrop(fractional.texture.color, 128),
                        cornerCrop(fractional.texture.depth, 128)}),
                 {PngBitDepth::Eight, true});

        std::printf("| material | mean angle (deg) | largest angle (deg) |\n|---|---|---|\n");
        for (const char* name : {"shaped_fabric", "three_layers"}) {
            const fs::path file = examples / (std::string(name) + ".json");
            const Composition paper = composeMaterial(file, NormalMode::Paper, size);
            const Composition consistent = composeMaterial(file, NormalMode::Consistent, size);
            const AngleStats stats = angleBetween(paper.texture.normal, consistent.texture.normal);
            std::printf("| %s | %.2f | %.2f |\n", name, stats.meanDegrees, stats.maxDegrees);
            writePng(output / ("normal_modes_" + std::string(name) + ".png"),
                     strip({encodeNormals(paper.texture.normal), encodeNormals(consistent.texture.normal),
                            angleMap(paper.texture.normal, consistent.texture.normal, 20.0)}),
                     {PngBitDepth::Eight, true});
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "composition_figures: %s\n", e.what());
        return 1;
    }
    return 0;
}
