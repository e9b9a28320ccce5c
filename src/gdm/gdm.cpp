#include "strata/gdm/gdm.h"

#include "strata/core/error.h"

#include <cmath>
#include <numbers>

namespace strata {

void validateGdmDims(const GdmDims& dims, double height, const std::string& what, std::size_t maxBytes) {
    const auto positive = [&](int value, const char* name) {
        if (value < 1)
            throw Error(ErrorKind::InvalidInput,
                        what + ": " + name + " must be >= 1, got " + std::to_string(value));
    };
    positive(dims.nx, "Nx");
    positive(dims.ny, "Ny");
    positive(dims.nz, "Nz");
    positive(dims.ntheta, "Ntheta");
    positive(dims.nphi, "Nphi");
    if (!(std::isfinite(height) && height > 0.0))
        throw Error(ErrorKind::InvalidInput,
                    what + ": the shell thickness H must be a number > 0, got " + formatNumber(height));
    // In double, so that absurd sizes cannot overflow the product.
    const double bytes = double(dims.nx) * double(dims.ny) * double(dims.nz) * double(dims.ntheta) *
                         double(dims.nphi) * double(sizeof(float));
    if (bytes > double(maxBytes))
        throw Error(ErrorKind::InvalidInput,
                    what + ": " + std::to_string(dims.nx) + "x" + std::to_string(dims.ny) + "x" +
                        std::to_string(dims.nz) + " voxels x " + std::to_string(dims.ntheta) + "x" +
                        std::to_string(dims.nphi) + " directions would need " +
                        formatNumber(std::round(bytes / double(1 << 20))) + " MiB, more than the " +
                        formatNumber(std::round(double(maxBytes) / double(1 << 20))) + " MiB allowed");
}

glm::dvec3 gdmDirection(const GdmDims& dims, int t, int s) {
    const double theta = (t + 0.5) * std::numbers::pi / dims.ntheta;
    const double phi = (s + 0.5) * 2.0 * std::numbers::pi / dims.nphi;
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

glm::dvec3 gdmVoxelCentre(const GdmDims& dims, double height, int i, int j, int k) {
    return {(i + 0.5) / dims.nx, (j + 0.5) / dims.ny, (k + 0.5) / dims.nz * height};
}

}  // namespace strata
