#include "strata/gdm/mesostructure_preview.h"

#include "core/staging_dir.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"
#include "strata/gdm/solid_mesh_io.h"
#include "strata/image/image_io.h"
#include "strata/image/srgb.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace strata {

namespace {

using glm::dvec3;

constexpr double kHitEpsilon = 2e-4;  // tile widths: a hit is where the bound drops below this
constexpr int kMaxSteps = 1000;

struct Box {
    dvec3 lo, hi;
};

// The ray's parameter interval inside the box, and the axis of the entry face; false if it misses.
bool intersectBox(const Box& box, const dvec3& origin, const dvec3& dir, double& tEnter, double& tExit,
                  int& entryAxis) {
    tEnter = -std::numeric_limits<double>::infinity();
    tExit = std::numeric_limits<double>::infinity();
    entryAxis = 2;
    for (int a = 0; a < 3; ++a) {
        if (dir[a] == 0.0) {
            if (origin[a] < box.lo[a] || origin[a] > box.hi[a]) return false;
            continue;
        }
        double t0 = (box.lo[a] - origin[a]) / dir[a];
        double t1 = (box.hi[a] - origin[a]) / dir[a];
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > tEnter) {
            tEnter = t0;
            entryAxis = a;
        }
        tExit = std::min(tExit, t1);
    }
    return tEnter <= tExit && tExit > 0.0;
}

// True if the segment from p towards `dir` meets the solid before leaving the slab 0 <= z <= H.
bool occluded(const Mesostructure& meso, dvec3 p, const dvec3& dir) {
    const double length = (meso.height() - p.z) / dir.z;
    double t = 0.0;
    for (int step = 0; step < kMaxSteps && t < length; ++step) {
        const double d = meso.distance(p + t * dir);
        if (d < kHitEpsilon) return true;
        t += d;
    }
    return false;
}

// The classic five-sample estimate along the normal: how much the distance falls short of the offset.
double ambientOcclusion(const Mesostructure& meso, const dvec3& p, const dvec3& n) {
    double occlusion = 0.0;
    double weight = 1.0;
    for (int i = 1; i <= 5; ++i) {
        const double h = 0.012 * i;
        occlusion += weight * std::max(0.0, h - meso.distance(p + h * n));
        weight *= 0.6;
    }
    return std::clamp(1.0 - 25.0 * occlusion, 0.0, 1.0);
}

dvec3 toLinear(const dvec3& c) {
    return {srgbToLinear(c.x), srgbToLinear(c.y), srgbToLinear(c.z)};
}

}  // namespace

Image renderMesostructurePreview(const Mesostructure& meso, const MesostructurePreviewParams& params) {
    if (params.size < 16 || params.size > 4096 || params.tiles < 1 || params.tiles > 8 ||
        !(params.elevationDegrees > 0.0 && params.elevationDegrees <= 90.0) ||
        !std::isfinite(params.azimuthDegrees))
        throw Error(ErrorKind::InvalidInput, "mesostructure preview: size " + std::to_string(params.size) +
                                                 ", tiles " + std::to_string(params.tiles) + ", elevation " +
                                                 formatNumber(params.elevationDegrees) +
                                                 " out of range ([16, 4096], [1, 8], (0, 90])");
    const double h = meso.height();
    const double span = params.tiles;
    const Box box{dvec3(0.0), dvec3(span, span, h)};
    const double elevation = params.elevationDegrees * std::numbers::pi / 180.0;
    const double azimuth = params.azimuthDegrees * std::numbers::pi / 180.0;
    const dvec3 toCamera(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                         std::sin(elevation));
    const dvec3 forward = -toCamera;
    const dvec3 right =
        params.elevationDegrees < 90.0 ? glm::normalize(glm::cross(forward, dvec3(0, 0, 1))) : dvec3(1, 0, 0);
    const dvec3 up = glm::cross(right, forward);
    // From the camera's side and above, rotated a quarter turn from it: grazing enough to cast shadows.
    const double lightAzimuth = azimuth + 0.4 * std::numbers::pi;
    const dvec3 toLight = glm::normalize(
        dvec3(std::cos(0.9) * std::cos(lightAzimuth), std::cos(0.9) * std::sin(lightAzimuth), std::sin(0.9)));

    // Frame the box: its corners projected on the image plane, a 3% margin.
    double xMin = 1e30, xMax = -1e30, yMin = 1e30, yMax = -1e30;
    for (int c = 0; c < 8; ++c) {
        const dvec3 corner((c & 1) ? span : 0.0, (c & 2) ? span : 0.0, (c & 4) ? h : 0.0);
        xMin = std::min(xMin, glm::dot(corner, right));
        xMax = std::max(xMax, glm::dot(corner, right));
        yMin = std::min(yMin, glm::dot(corner, up));
        yMax = std::max(yMax, glm::dot(corner, up));
    }
    const double extent = 1.06 * std::max(xMax - xMin, yMax - yMin);
    const double xMid = 0.5 * (xMin + xMax), yMid = 0.5 * (yMin + yMax);
    const dvec3 centre(0.5 * span, 0.5 * span, 0.5 * h);
    const double back = 4.0 * span;  // the ray origins lie this far behind the box's centre

    Image image = Image::uninitialized(params.size, params.size, 3);
    parallelFor(0, params.size, [&](int row) {
        for (int column = 0; column < params.size; ++column) {
            const double x = xMid + ((column + 0.5) / params.size - 0.5) * extent;
            const double y = yMid + (0.5 - (row + 0.5) / params.size) * extent;
            const dvec3 origin = centre + (x - glm::dot(centre, right)) * right +
                                 (y - glm::dot(centre, up)) * up - back * forward;
            // Background: a soft vertical gradient.
            dvec3 colour =
                glm::mix(dvec3(0.80, 0.82, 0.86), dvec3(0.55, 0.58, 0.64), double(row) / params.size);
            double tEnter, tExit;
            int axis;
            if (intersectBox(box, origin, forward, tEnter, tExit, axis)) {
                dvec3 hit, normal, albedo;
                bool found = false;
                double t = std::max(tEnter, 0.0);
                dvec3 p = origin + t * forward;
                if (meso.distance(p) < 0.0) {
                    // The cut face of the box.
                    found = true;
                    hit = p;
                    normal = dvec3(0.0);
                    normal[axis] = forward[axis] > 0.0 ? -1.0 : 1.0;
                } else {
                    for (int step = 0; step < kMaxSteps && t <= tExit; ++step) {
                        p = origin + t * forward;
                        const double d = meso.distance(p);
                        if (d < kHitEpsilon) {
                            found = true;
                            hit = p;
                            normal = meso.normal(p);
                            break;
                        }
                        t += d;
                    }
                }
                bool floor = false;
                if (!found && forward.z < 0.0) {
                    // The floor z = 0 under the tiles.
                    const double tFloor = -origin.z / forward.z;
                    hit = origin + tFloor * forward;
                    if (hit.x >= 0.0 && hit.x <= span && hit.y >= 0.0 && hit.y <= span) {
                        found = floor = true;
                        normal = dvec3(0, 0, 1);
                        const double bu = std::abs(hit.x - std::round(hit.x));
                        const double bv = std::abs(hit.y - std::round(hit.y));
                        albedo = std::min(bu, bv) < 0.006 ? dvec3(0.12) : dvec3(0.42);
                    }
                }
                if (found) {
                    if (!floor) albedo = meso.sample(hit - 0.5 * kHitEpsilon * normal).albedo;
                    const dvec3 lifted = hit + 2.0 * kHitEpsilon * normal;
                    const double lambert = std::max(0.0, glm::dot(normal, toLight));
                    const double lit = lambert > 0.0 && !occluded(meso, lifted, toLight) ? 1.0 : 0.0;
                    const double ambient = floor ? 1.0 : ambientOcclusion(meso, lifted, normal);
                    const dvec3 linear = toLinear(albedo) * (0.22 * ambient + 0.95 * lambert * lit);
                    colour = {linearToSrgb(linear.x), linearToSrgb(linear.y), linearToSrgb(linear.z)};
                }
            }
            for (int c = 0; c < 3; ++c) image.at(column, row, c) = static_cast<float>(colour[c]);
        }
    });
    return image;
}

std::vector<std::filesystem::path> writeMesostructureOutputs(const std::filesystem::path& dir,
                                                             const SolidMesh& mesh, const Image& preview) {
    namespace fs = std::filesystem;
    detail::StagingDir staging(dir);
    writeSolidObj(staging.path() / "mesh.obj", mesh);
    PngWriteOptions png;
    png.bitDepth = PngBitDepth::Eight;
    writePng(staging.path() / "preview.png", preview, png);
    return staging.moveInto(dir, {"mesh.obj", "preview.png"});
}

}  // namespace strata
