#include "strata/environment/environment.h"

#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/parallel.h"
#include "strata/image/image_io.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <system_error>
#include <utility>

namespace strata {

namespace {

constexpr double kPi = std::numbers::pi;

[[noreturn]] void fail(ErrorKind kind, const std::filesystem::path& path, const std::string& what) {
    throw Error(kind, path.string() + ": " + what);
}

void checkSize(int width, int height) {
    for (const int size : {width, height})
        if (size < 1 || size > Image::kMaxDimension)
            throw Error(ErrorKind::InvalidInput, "environment map size " + std::to_string(width) + "x" +
                                                     std::to_string(height) + ": each side must be in [1, " +
                                                     std::to_string(Image::kMaxDimension) + "]");
}

}  // namespace

glm::dvec3 sphericalDirection(double polar, double azimuth) {
    const double sinPolar = std::sin(polar);
    return {sinPolar * std::cos(azimuth), sinPolar * std::sin(azimuth), std::cos(polar)};
}

glm::dvec3 equirectTexelDirection(int column, int row, int width, int height) {
    return sphericalDirection((row + 0.5) * kPi / height, (column + 0.5) * 2.0 * kPi / width);
}

double equirectTexelSolidAngle(int row, int width, int height) {
    return 2.0 * kPi / width * (std::cos(row * kPi / height) - std::cos((row + 1) * kPi / height));
}

EquirectTexel equirectTexelOf(const glm::dvec3& direction, int width, int height) {
    const double length = glm::length(direction);
    STRATA_CHECK(std::isfinite(length) && length > 0.0);
    const glm::dvec3 d = direction / length;
    const double polar = std::acos(std::clamp(d.z, -1.0, 1.0));
    double azimuth = std::atan2(d.y, d.x);
    if (azimuth < 0.0) azimuth += 2.0 * kPi;
    EquirectTexel texel;
    texel.column = std::clamp(static_cast<int>(std::floor(azimuth / (2.0 * kPi) * width)), 0, width - 1);
    texel.row = std::clamp(static_cast<int>(std::floor(polar / kPi * height)), 0, height - 1);
    return texel;
}

ShColor projectEquirect(const Image& equirect) {
    STRATA_CHECK(!equirect.empty());
    const int channels = equirect.channels();
    STRATA_CHECK(channels == 1 || channels == 3 || channels == 4);
    const int width = equirect.width();
    const int height = equirect.height();
    // One partial sum per row (rows in parallel), added in row order afterwards: the same numbers on every
    // run whatever the threads do.
    std::vector<ShColor> rowSums(static_cast<std::size_t>(height));
    parallelFor(0, height, [&](int row) {
        const double solidAngle = equirectTexelSolidAngle(row, width, height);
        ShColor sum{};
        for (int column = 0; column < width; ++column) {
            const float* texel = equirect.row(row) + static_cast<std::ptrdiff_t>(column) * channels;
            const glm::dvec3 value =
                channels == 1 ? glm::dvec3(static_cast<double>(texel[0]))
                              : glm::dvec3(static_cast<double>(texel[0]), static_cast<double>(texel[1]),
                                           static_cast<double>(texel[2]));
            if (value == glm::dvec3(0.0)) continue;
            const ShVector basis = shEvaluate(equirectTexelDirection(column, row, width, height));
            for (int k = 0; k < kShCount; ++k) sum[k] += value * basis[k];
        }
        for (int k = 0; k < kShCount; ++k) sum[k] *= solidAngle;
        rowSums[static_cast<std::size_t>(row)] = sum;
    });
    ShColor result{};
    for (const ShColor& sum : rowSums)
        for (int k = 0; k < kShCount; ++k) result[k] += sum[k];
    return result;
}

Image readEnvironmentMap(const std::filesystem::path& path) {
    const ImageInfo info = readImageInfo(path);
    if (info.format != ImageFormat::Exr)
        fail(ErrorKind::InvalidInput, path,
             std::string(
                 "an environment map must be OpenEXR (linear radiance, CONVENTIONS §9), this file is ") +
                 toString(info.format));
    const Image image = readImage(path);
    const int channels = image.channels();
    Image rgb = Image::uninitialized(image.width(), image.height(), 3);
    static const char* const kChannelNames[] = {"R", "G", "B"};
    for (int row = 0; row < image.height(); ++row)
        for (int column = 0; column < image.width(); ++column)
            for (int c = 0; c < 3; ++c) {
                const int source = channels <= 2 ? 0 : c;
                const float value = image.at(column, row, source);
                if (!std::isfinite(value) || value < 0.0f)
                    fail(ErrorKind::InvalidInput, path,
                         "texel (column " + std::to_string(column) + ", row " + std::to_string(row) +
                             ") channel " +
                             (channels <= 2 ? std::string("Y") : std::string(kChannelNames[c])) + " is " +
                             formatNumber(static_cast<double>(value)) +
                             ": radiance must be finite and non-negative");
                rgb.at(column, row, c) = value;
            }
    return rgb;
}

Image renderEquirect(const RadianceFunction& radiance, int width, int height) {
    STRATA_CHECK(width >= 1 && width <= Image::kMaxDimension && height >= 1 &&
                 height <= Image::kMaxDimension);
    Image image = Image::uninitialized(width, height, 3);
    parallelFor(0, height, [&](int row) {
        float* out = image.row(row);
        for (int column = 0; column < width; ++column) {
            const glm::dvec3 value = radiance(equirectTexelDirection(column, row, width, height));
            for (int c = 0; c < 3; ++c) out[3 * column + c] = static_cast<float>(value[c]);
        }
    });
    return image;
}

Environment::Environment(std::string name, RadianceFunction radiance, int width, int height)
    : mName(std::move(name)), mRadiance(std::move(radiance)) {
    STRATA_CHECK(static_cast<bool>(mRadiance));
    mMap = renderEquirect(mRadiance, width, height);
    mSh = projectEquirect(mMap);
}

Environment::Environment(std::string name, Image equirect)
    : mName(std::move(name)), mMap(std::move(equirect)) {
    STRATA_CHECK(!mMap.empty() && mMap.channels() == 3);
    mSh = projectEquirect(mMap);
}

glm::dvec3 Environment::radiance(const glm::dvec3& direction) const {
    if (mRadiance) return mRadiance(direction);
    const EquirectTexel texel = equirectTexelOf(direction, mMap.width(), mMap.height());
    return {static_cast<double>(mMap.at(texel.column, texel.row, 0)),
            static_cast<double>(mMap.at(texel.column, texel.row, 1)),
            static_cast<double>(mMap.at(texel.column, texel.row, 2))};
}

Environment makeEnvironment(const std::string& name, int width, int height) {
    RadianceFunction radiance = skyRadiance(name);
    checkSize(width, height);
    return Environment(name, std::move(radiance), width, height);
}

Environment loadEnvironment(const std::filesystem::path& path) {
    return Environment(path.string(), readEnvironmentMap(path));
}

Environment openEnvironment(const std::string& nameOrPath, int width, int height) {
    const std::vector<std::string> names = environmentList();
    if (std::find(names.begin(), names.end(), nameOrPath) != names.end())
        return makeEnvironment(nameOrPath, width, height);
    std::error_code error;
    if (std::filesystem::exists(nameOrPath, error)) return loadEnvironment(nameOrPath);
    std::string list;
    for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
    throw Error(ErrorKind::InvalidInput, "environment '" + nameOrPath +
                                             "' is neither a built-in environment (" + list +
                                             ") nor an existing file");
}

}  // namespace strata
