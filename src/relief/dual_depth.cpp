#include "strata/relief/dual_depth.h"

#include "core/json_reader.h"
#include "core/staging_dir.h"
#include "strata/core/check.h"
#include "strata/core/error.h"
#include "strata/core/file.h"
#include "strata/core/parallel.h"
#include "strata/core/version.h"
#include "strata/image/image_io.h"

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

namespace fs = std::filesystem;
using nlohmann::json;

namespace strata {

namespace {

constexpr const char* kSidecar = "strata.json";
constexpr const char* kPacked = "packed.png";

// Barycentric coordinates down to -kInsideEpsilon count as inside: a texel centre on an edge shared by two
// triangles is then inside both (the two edge functions are computed from differently ordered operands and
// need not round to exactly opposite values), never inside neither. The overshoot it allows is 1e-9 of a
// triangle, far below the 16-bit depth step.
constexpr double kInsideEpsilon = 1e-9;

// Rows per parallel task: a band of rows shares the triangles binned to it.
constexpr int kRowsPerBand = 8;

// A triangle projected onto the footprint grid, in texel units (integer x, y = texel centres).
struct ProjectedTriangle {
    std::array<double, 3> x, y, a;  // column, row, axis coordinate of each corner
    std::array<std::uint32_t, 3> index;
    double area2;  // twice the signed area in texel units; 0 for an edge-on triangle
};

// The other two axes of `axis` (tile T and B; the axis itself is N): for z: x, y; for x: y, z; for y: z, x.
std::array<int, 3> frameOf(Axis axis) {
    const int n = axis == Axis::X ? 0 : axis == Axis::Y ? 1 : 2;
    return {(n + 1) % 3, (n + 2) % 3, n};
}

fs::path sidecarPathOf(const fs::path& path) {
    std::error_code ec;
    return fs::is_directory(path, ec) ? path / kSidecar : path;
}

}  // namespace

const char* toString(Axis axis) {
    switch (axis) {
        case Axis::X:
            return "x";
        case Axis::Y:
            return "y";
        case Axis::Z:
            return "z";
    }
    return "?";
}

Axis parseAxis(const std::string& text) {
    if (text == "x") return Axis::X;
    if (text == "y") return Axis::Y;
    if (text == "z") return Axis::Z;
    throw Error(ErrorKind::InvalidInput, "axis must be x, y or z, got \"" + text + "\"");
}

DualDepthTexture makeDualDepth(const Mesh& mesh, Axis axis, int size) {
    if (size < 1 || size > Image::kMaxDimension)
        throw Error(ErrorKind::InvalidInput, "dual-depth size must be in [1, " +
                                                 std::to_string(Image::kMaxDimension) + "], got " +
                                                 std::to_string(size));
    if (mesh.indices.size() < 3)
        throw Error(ErrorKind::InvalidInput, mesh.name + ": has no triangles to sample");
    // Plain variables, not a structured binding: the lambdas below capture them (clang 14, which builds the
    // fuzzers, cannot capture a structured binding).
    const std::array<int, 3> frame = frameOf(axis);
    const int ti = frame[0], bi = frame[1], ni = frame[2];
    const Bounds bounds = meshBounds(mesh);
    const glm::dvec3 lower(bounds.min), upper(bounds.max);
    const double extentT = upper[ti] - lower[ti];
    const double extentB = upper[bi] - lower[bi];
    const double extent = upper[ni] - lower[ni];
    const double side = std::max(extentT, extentB);
    // Flatter than float positions resolve relative to the object: the depth or the footprint would be
    // noise (and S = E / L would be 0 or infinite).
    const double largest = std::max(side, extent);
    if (!(extent > 1e-6 * largest))
        throw Error(ErrorKind::InvalidInput, mesh.name + ": is flat along " + toString(axis) + " (extent " +
                                                 formatNumber(extent) +
                                                 "); a dual-depth texture needs a solid");
    if (!(side > 1e-6 * largest))
        throw Error(ErrorKind::InvalidInput, mesh.name + ": is flat across " + toString(axis) +
                                                 " (footprint " + formatNumber(side) + ")");

    // Footprint: the square of side L centred on the bounds; row 0 is the top (largest B).
    const double originT = 0.5 * (lower[ti] + upper[ti]) - 0.5 * side;
    const double topB = 0.5 * (lower[bi] + upper[bi]) + 0.5 * side;
    const double texelsPerUnit = size / side;

    const std::size_t triangleCount = mesh.indices.size() / 3;
    std::vector<ProjectedTriangle> triangles(triangleCount);
    parallelForChunks(
        std::size_t{0}, triangleCount,
        [&](std::size_t first, std::size_t last) {
            for (std::size_t t = first; t != last; ++t) {
                ProjectedTriangle& p = triangles[t];
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t index = mesh.indices[3 * t + std::size_t(k)];
                    STRATA_CHECK_LT(index, mesh.vertices.size());
                    const glm::dvec3 position(mesh.vertices[index].position);
                    p.index[std::size_t(k)] = index;
                    p.x[std::size_t(k)] = (position[ti] - originT) * texelsPerUnit - 0.5;
                    p.y[std::size_t(k)] = (topB - position[bi]) * texelsPerUnit - 0.5;
                    p.a[std::size_t(k)] = position[ni];
                }
                p.area2 = (p.x[1] - p.x[0]) * (p.y[2] - p.y[0]) - (p.y[1] - p.y[0]) * (p.x[2] - p.x[0]);
            }
        },
        std::size_t{4096});

    // Bin each triangle to the row bands it spans, in triangle order, so that every band sees its
    // triangles in index order and ties resolve the same way on every run (the first triangle wins).
    const int bandCount = (size + kRowsPerBand - 1) / kRowsPerBand;
    std::vector<std::vector<std::uint32_t>> bands(static_cast<std::size_t>(bandCount));
    for (std::size_t t = 0; t < triangleCount; ++t) {
        const ProjectedTriangle& p = triangles[t];
        // An edge-on triangle covers no area; the lines through its edges are covered (inclusively) by
        // its neighbours.
        if (!(std::abs(p.area2) > 1e-12)) continue;
        const double minY = std::min({p.y[0], p.y[1], p.y[2]});
        const double maxY = std::max({p.y[0], p.y[1], p.y[2]});
        const int first = std::max(0, int(std::ceil(minY - 1e-6)));
        const int last = std::min(size - 1, int(std::floor(maxY + 1e-6)));
        for (int band = first / kRowsPerBand; first <= last && band <= last / kRowsPerBand; ++band)
            bands[std::size_t(band)].push_back(std::uint32_t(t));
    }

    const double maxA = upper[ni];
    DualDepthTexture texture;
    texture.axis = axis;
    texture.depthScale = extent / side;
    texture.front = Image::uninitialized(size, size, 1);
    texture.back = Image::uninitialized(size, size, 1);
    texture.normal = Image::uninitialized(size, size, 3);

    parallelFor(0, bandCount, [&](int band) {
        const int row0 = band * kRowsPerBand;
        const int rows = std::min(kRowsPerBand, size - row0);
        const std::size_t count = std::size_t(rows) * std::size_t(size);
        constexpr double kInf = std::numeric_limits<double>::infinity();
        std::vector<double> front(count, -kInf), back(count, kInf);
        std::vector<glm::dvec3> normal(count, glm::dvec3(0.0, 0.0, 1.0));
        for (const std::uint32_t t : bands[std::size_t(band)]) {
            const ProjectedTriangle& p = triangles[t];
            const double minX = std::min({p.x[0], p.x[1], p.x[2]});
            const double maxX = std::max({p.x[0], p.x[1], p.x[2]});
            const double minY = std::min({p.y[0], p.y[1], p.y[2]});
            const double maxY = std::max({p.y[0], p.y[1], p.y[2]});
            const int x0 = std::max(0, int(std::ceil(minX - 1e-6)));
            const int x1 = std::min(size - 1, int(std::floor(maxX + 1e-6)));
            const int y0 = std::max(row0, int(std::ceil(minY - 1e-6)));
            const int y1 = std::min(row0 + rows - 1, int(std::floor(maxY + 1e-6)));
            const double inverseArea = 1.0 / p.area2;
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) {
                    // Barycentric coordinates from the edge functions, normalised by the area.
                    std::array<double, 3> w;
                    for (int k = 0; k < 3; ++k) {
                        const std::size_t i = std::size_t((k + 1) % 3), j = std::size_t((k + 2) % 3);
                        w[std::size_t(k)] =
                            ((p.x[j] - p.x[i]) * (y - p.y[i]) - (p.y[j] - p.y[i]) * (x - p.x[i])) *
                            inverseArea;
                    }
                    if (w[0] < -kInsideEpsilon || w[1] < -kInsideEpsilon || w[2] < -kInsideEpsilon) continue;
                    const double a = w[0] * p.a[0] + w[1] * p.a[1] + w[2] * p.a[2];
                    const std::size_t texel = std::size_t(y - row0) * std::size_t(size) + std::size_t(x);
                    back[texel] = std::min(back[texel], a);
                    if (!(a > front[texel])) continue;
                    front[texel] = a;
                    glm::dvec3 n(0.0);
                    for (int k = 0; k < 3; ++k)
                        n += w[std::size_t(k)] * glm::dvec3(mesh.vertices[p.index[std::size_t(k)]].normal);
                    if (!(glm::length(n) > 1e-12)) {
                        // Opposite vertex normals cancel: the face normal is the best answer left.
                        const auto& v = mesh.vertices;
                        const glm::dvec3 p0(v[p.index[0]].position), p1(v[p.index[1]].position),
                            p2(v[p.index[2]].position);
                        n = glm::cross(p1 - p0, p2 - p0);
                    }
                    n = glm::normalize(n);
                    normal[texel] = {n[ti], n[bi], n[ni]};
                }
        }
        for (int y = 0; y < rows; ++y)
            for (int x = 0; x < size; ++x) {
                const std::size_t texel = std::size_t(y) * std::size_t(size) + std::size_t(x);
                const bool hit = front[texel] > -kInf;
                // Clamped: the inclusive edge test may extrapolate a hair beyond the bounds.
                texture.front.at(x, row0 + y) =
                    hit ? float(std::clamp((maxA - front[texel]) / extent, 0.0, 1.0)) : 1.0f;
                texture.back.at(x, row0 + y) =
                    hit ? float(std::clamp((maxA - back[texel]) / extent, 0.0, 1.0)) : 0.0f;
                // Facing up: packed.png keeps only nx, ny and a reader recovers nz = sqrt(1 - nx^2 - ny^2)
                // >= 0, so a grazing front normal that leans down (interpolation at the silhouette) has its
                // N component mirrored, which keeps its direction across the tile.
                const glm::dvec3& n = normal[texel];
                float* out = &texture.normal.at(x, row0 + y);
                out[0] = float(n.x);
                out[1] = float(n.y);
                out[2] = float(std::abs(n.z));
            }
    });
    return texture;
}

std::vector<fs::path> writeDualDepth(const fs::path& dir, const DualDepthTexture& texture,
                                     const std::string& source) {
    const int width = texture.front.width();
    const int height = texture.front.height();
    STRATA_CHECK(!texture.front.empty());
    STRATA_CHECK(texture.back.width() == width && texture.back.height() == height);
    STRATA_CHECK(texture.normal.width() == width && texture.normal.height() == height &&
                 texture.normal.channels() == 3);
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw Error(ErrorKind::Io, dir.string() + ": exists and is not a directory");

    Image packed(width, height, 4);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            packed.at(x, y, 0) = texture.normal.at(x, y, 0) * 0.5f + 0.5f;
            packed.at(x, y, 1) = texture.normal.at(x, y, 1) * 0.5f + 0.5f;
            packed.at(x, y, 2) = texture.front.at(x, y);
            packed.at(x, y, 3) = texture.back.at(x, y);
        }
    json sidecar;
    sidecar["format"] = kDualDepthFormat;
    sidecar["version"] = 1;
    sidecar["tool"] = std::string("strata ") + kVersion;
    sidecar["width"] = width;
    sidecar["height"] = height;
    sidecar["depth_scale"] = texture.depthScale;
    sidecar["axis"] = toString(texture.axis);
    sidecar["source"] = source;
    sidecar["packed"] = {{"file", kPacked},
                         {"layout",
                          "R = nx * 0.5 + 0.5, G = ny * 0.5 + 0.5, B = front depth, A = back depth; "
                          "nz = sqrt(1 - nx^2 - ny^2); a line that misses has front 1 > back 0"}};

    // Both files are finished in a staging directory first; the sidecar, which is what makes `dir` a
    // dual-depth texture, moves into place last.
    detail::StagingDir staging(dir);
    writePng(staging.path() / kPacked, packed, {PngBitDepth::Sixteen, false});
    writeTextFileAtomic(staging.path() / kSidecar, sidecar.dump(2) + "\n");
    return staging.moveInto(dir, {kPacked, kSidecar});
}

DualDepthTexture readDualDepth(const fs::path& path) {
    const fs::path sidecarPath = sidecarPathOf(path);
    const json sidecar = detail::readJsonFile(sidecarPath);
    detail::JsonObjectReader reader(sidecar, "", sidecarPath.string());
    const auto format = reader.string("format");
    if (format != std::string(kDualDepthFormat))
        reader.fail("format", std::string("must be \"") + kDualDepthFormat + "\", got " +
                                  (format ? "\"" + *format + "\"" : std::string("nothing")));
    const auto version = reader.integer("version", 0, std::numeric_limits<int>::max());
    if (!version) reader.fail("version", "is missing");
    if (*version != 1)
        throw Error(ErrorKind::Unsupported, sidecarPath.string() + ": version " + std::to_string(*version) +
                                                " is not supported (this Strata reads version 1)");
    const auto width = reader.integer("width", 1, Image::kMaxDimension);
    const auto height = reader.integer("height", 1, Image::kMaxDimension);
    if (!width) reader.fail("width", "is missing");
    if (!height) reader.fail("height", "is missing");
    const auto depthScale = reader.number("depth_scale");
    if (!depthScale || !(*depthScale > 0.0)) reader.fail("depth_scale", "must be a positive number");
    const auto axisText = reader.string("axis");
    if (!axisText) reader.fail("axis", "is missing");

    DualDepthTexture texture;
    texture.depthScale = *depthScale;
    try {
        texture.axis = parseAxis(*axisText);
    } catch (const Error& e) {
        reader.fail("axis", e.what());
    }
    const fs::path packedPath = sidecarPath.parent_path() / kPacked;
    const Image packed = readImage(packedPath);
    if (packed.channels() != 4 || packed.width() != *width || packed.height() != *height)
        throw Error(ErrorKind::InvalidInput,
                    packedPath.string() + ": must be 4 channels of " + std::to_string(*width) + "x" +
                        std::to_string(*height) + " (" + sidecarPath.string() +
                        " \"width\", \"height\"), got " + std::to_string(packed.channels()) +
                        " channel(s) of " + std::to_string(packed.width()) + "x" +
                        std::to_string(packed.height()));
    const int w = packed.width(), h = packed.height();
    texture.front = Image(w, h, 1);
    texture.back = Image(w, h, 1);
    texture.normal = Image(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double nx = static_cast<double>(packed.at(x, y, 0)) * 2.0 - 1.0;
            double ny = static_cast<double>(packed.at(x, y, 1)) * 2.0 - 1.0;
            const double tangential = nx * nx + ny * ny;
            if (tangential > 1.0) {
                // Quantisation can push a horizontal normal a hair past the unit circle.
                const double length = std::sqrt(tangential);
                nx /= length;
                ny /= length;
            }
            float* n = &texture.normal.at(x, y);
            n[0] = float(nx);
            n[1] = float(ny);
            n[2] = float(std::sqrt(std::max(0.0, 1.0 - nx * nx - ny * ny)));
            texture.front.at(x, y) = packed.at(x, y, 2);
            texture.back.at(x, y) = packed.at(x, y, 3);
        }
    return texture;
}

bool isDualDepth(const fs::path& path) {
    try {
        const fs::path sidecarPath = sidecarPathOf(path);
        std::error_code ec;
        if (!fs::is_regular_file(sidecarPath, ec)) return false;
        const json sidecar = json::parse(readTextFile(sidecarPath));
        return sidecar.is_object() && sidecar.value("format", "") == kDualDepthFormat;
    } catch (const std::exception&) {
        return false;
    }
}

}  // namespace strata
