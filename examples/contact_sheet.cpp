// Writes a contact sheet of the built-in procedural relief library (strata/relief/patterns.h):
// one row per pattern, in patternList() order, showing depth | normal | colour.
//
//     example_contact_sheet [DIR]      (default DIR: docs/img)
//
// Writes DIR/patterns_contact_sheet.png (8-bit RGB). Depth is shown as stored (black = the top,
// white = the deepest point), normals as stored in files (n * 0.5 + 0.5), colour as sRGB.
#include "strata/core/error.h"
#include "strata/image/image_io.h"
#include "strata/relief/patterns.h"

#include <cstdio>
#include <exception>
#include <filesystem>

namespace {

constexpr int kTile = 160;  // pixels; generated at this size, not resampled
constexpr int kGap = 12;
constexpr float kBackground = 0.13f;

// Copies a 1- or 3-channel tile into the sheet with its top-left corner at (x0, y0).
void blit(strata::Image& sheet, const strata::Image& tile, int x0, int y0) {
    for (int y = 0; y < tile.height(); ++y)
        for (int x = 0; x < tile.width(); ++x)
            for (int c = 0; c < 3; ++c)
                sheet.at(x0 + x, y0 + y, c) = tile.at(x, y, tile.channels() == 1 ? 0 : c);
}

}  // namespace

int main(int argc, char** argv) {
    const std::filesystem::path dir = argc > 1 ? argv[1] : "docs/img";
    try {
        const auto& patterns = strata::patternList();
        const int rows = static_cast<int>(patterns.size());
        strata::Image sheet(3 * kTile + 4 * kGap, rows * kTile + (rows + 1) * kGap, 3, kBackground);
        for (int row = 0; row < rows; ++row) {
            strata::PatternParams params;
            params.size = kTile;
            const strata::ReliefTexture texture = strata::makePattern(patterns[row].name, params);
            const int y0 = kGap + row * (kTile + kGap);
            blit(sheet, texture.depth, kGap, y0);
            blit(sheet, strata::encodeNormals(texture.normal), 2 * kGap + kTile, y0);
            blit(sheet, texture.color, 3 * kGap + 2 * kTile, y0);
            std::printf("%2d  %-14s %s\n", row + 1, patterns[row].name.c_str(),
                        patterns[row].description.c_str());
        }
        std::filesystem::create_directories(dir);
        const std::filesystem::path path = dir / "patterns_contact_sheet.png";
        strata::writePng(path, sheet, {strata::PngBitDepth::Eight, true});
        std::printf("wrote %s\n", path.string().c_str());
    } catch (const strata::Error& error) {
        std::fprintf(stderr, "example_contact_sheet: %s\n", error.what());
        return strata::exitCode(error.kind());
    } catch (const std::exception& error) {
        std::fprintf(stderr, "example_contact_sheet: %s\n", error.what());
        return 1;
    }
    return 0;
}
