// docs/environment.md's pictures and numbers: each built-in sky as a 512 x 256 equirectangular map (top) and
// the diffuse shading its band-3 SH gives, E / pi for albedo 1 (bottom), both tone-mapped x / (1 + x) after
// an exposure, then sRGB-encoded. Prints each sky's DC term, mean radiance, band-1 direction and the
// irradiance at +z, and the DC term's relative difference against a 2^20-point spherical Fibonacci lattice.
// Usage: example_environment_figures OUT_DIR   (writes OUT_DIR/env_<name>.png)
#include "strata/core/error.h"
#include "strata/environment/environment.h"
#include "strata/image/image_io.h"
#include "strata/image/srgb.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

namespace {

constexpr double kPi = std::numbers::pi;

float toneMap(double value, double exposure) {
    const double x = std::max(value, 0.0) * exposure;
    return static_cast<float>(strata::linearToSrgb(x / (1.0 + x)));
}

}  // namespace

int main(int argc, char** argv) try {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
        return 1;
    }
    const std::filesystem::path out = argv[1];
    constexpr int kWidth = 512, kHeight = 256, kGap = 4;
    for (const std::string& name : strata::environmentList()) {
        const strata::Environment environment = strata::makeEnvironment(name, kWidth, kHeight);
        const strata::ShColor irradiance = strata::shIrradiance(environment.sh());
        const double exposure = name == "studio" ? 2.0 : 1.5;
        strata::Image picture(kWidth, 2 * kHeight + kGap, 3, 1.0f);
        for (int row = 0; row < kHeight; ++row)
            for (int column = 0; column < kWidth; ++column) {
                const glm::dvec3 d = strata::equirectTexelDirection(column, row, kWidth, kHeight);
                const glm::dvec3 radiance = environment.radiance(d);
                const glm::dvec3 shading = strata::shReconstruct(irradiance, d) / kPi;
                for (int c = 0; c < 3; ++c) {
                    picture.at(column, row, c) = toneMap(radiance[c], exposure);
                    picture.at(column, kHeight + kGap + row, c) = toneMap(shading[c], exposure);
                }
            }
        strata::writePng(out / ("env_" + name + ".png"), picture, {strata::PngBitDepth::Eight, true});

        constexpr int kPoints = 1 << 20;
        const double goldenAngle = kPi * (3.0 - std::sqrt(5.0));
        glm::dvec3 sum(0.0);
        for (int i = 0; i < kPoints; ++i) {
            const double z = 1.0 - (2.0 * i + 1.0) / kPoints;
            const double r = std::sqrt(1.0 - z * z);
            sum += environment.radiance({r * std::cos(goldenAngle * i), r * std::sin(goldenAngle * i), z});
        }
        const glm::dvec3 lattice = sum / static_cast<double>(kPoints) * std::sqrt(4.0 * kPi);
        const glm::dvec3 dc = environment.sh()[0];
        const glm::dvec3 mean = dc / std::sqrt(4.0 * kPi);
        const glm::dvec3 direction = strata::shDominantDirection(strata::shLuminance(environment.sh()));
        const glm::dvec3 up = strata::shReconstruct(irradiance, {0.0, 0.0, 1.0});
        std::printf(
            "%-13s c00 (%.4f, %.4f, %.4f)  mean L (%.4f, %.4f, %.4f)  band-1 direction (%.3f, %.3f, %.3f)  "
            "E(+z) (%.3f, %.3f, %.3f)  c00 vs lattice %+.1e %+.1e %+.1e\n",
            name.c_str(), dc.x, dc.y, dc.z, mean.x, mean.y, mean.z, direction.x, direction.y, direction.z,
            up.x, up.y, up.z, dc.x / lattice.x - 1.0, dc.y / lattice.y - 1.0, dc.z / lattice.z - 1.0);
    }
    return 0;
} catch (...) {
    return strata::reportCurrentException("example_environment_figures");
}
