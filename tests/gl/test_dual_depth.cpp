// Dual-depth relief (Policarpo et al. 2005, Sec. 4; uploadDualDepth, Technique::DualDepth) on the
// verification quad against the analytic object it samples: a sphere below the quad.
#include "gl_test_support.h"
#include "strata/core/error.h"
#include "strata/gl/gpu_material.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/gl/relief_renderer.h"
#include "strata/mesh/builtin_meshes.h"
#include "strata/relief/dual_depth.h"
#include "strata/relief/relief_texture.h"

#include <glm/geometric.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

namespace strata::gl {
namespace {

class DualDepthGl : public test::GlTest {};

constexpr int kSize = 128;
constexpr int kPicture = 160;
const glm::dvec3 kCentre(0.5, 0.5, -0.5);  // world = tile units (the quad: x, y in [0, 1] at z = 0)
constexpr double kRadius = 0.4;

// The sphere sampled as strata/relief/dual_depth.h lays it out: S = 1 (its depth range [0, 1] is one tile
// deep), texel (i, j) at u = (i + 0.5) / W, v = 1 - (j + 0.5) / H.
DualDepthTexture sphereTexture() {
    DualDepthTexture texture;
    texture.front = Image(kSize, kSize, 1, 1.0f);
    texture.back = Image(kSize, kSize, 1, 0.0f);
    texture.normal = Image(kSize, kSize, 3, 0.0f);
    texture.depthScale = 1.0;
    for (int j = 0; j < kSize; ++j) {
        for (int i = 0; i < kSize; ++i) {
            const double u = (i + 0.5) / kSize, v = 1.0 - (j + 0.5) / kSize;
            const double r2 = (u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5);
            texture.normal.at(i, j, 2) = 1.0f;
            if (r2 >= kRadius * kRadius) continue;
            const double h = std::sqrt(kRadius * kRadius - r2);
            texture.front.at(i, j) = static_cast<float>(-kCentre.z - h);
            texture.back.at(i, j) = static_cast<float>(-kCentre.z + h);
            texture.normal.at(i, j, 0) = static_cast<float>((u - 0.5) / kRadius);
            texture.normal.at(i, j, 1) = static_cast<float>((v - 0.5) / kRadius);
            texture.normal.at(i, j, 2) = static_cast<float>(h / kRadius);
        }
    }
    return texture;
}

// d of the first point of the ray inside the sphere, or nullopt.
std::optional<double> sphereDepth(const glm::dvec3& eye, const glm::dvec3& direction) {
    const glm::dvec3 o = eye - kCentre;
    const double b = glm::dot(o, direction), c = glm::dot(o, o) - kRadius * kRadius;
    const double disc = b * b - c;
    if (disc < 0.0) return std::nullopt;
    const double t = -b - std::sqrt(disc);
    return -(eye.z + t * direction.z);
}

// Where the ray's whole path through the depth range stays over the quad, so that the texture's repeat
// plays no part, the impostor shows the sphere where the sphere is, at its depth: hit/miss agreement away
// from the silhouette (rays passing within 1.5 texels of it, where bilinear filtering of front and back
// rounds the outline), and depth within the search bracket plus the chord error of a 128^2 sampling.
TEST_F(DualDepthGl, ImpostorShowsTheSphereWhereItIs) {
    const GpuMaterial material = uploadDualDepth(sphereTexture());
    ASSERT_TRUE(material.isDualDepth());
    ReliefRenderer renderer;
    const GpuMesh quad = uploadMesh(makeBuiltinMesh("quad"));
    for (const double angle : {0.0, 20.0, 35.0}) {
        const double a = angle * 3.14159265358979323846 / 180.0;
        RenderRequest request;
        request.objects.push_back({&quad, glm::dmat4(1.0), &material, glm::dvec3(0.8)});
        request.camera.target = {0.5, 0.5, 0.0};
        request.camera.eye = request.camera.target + 2.2 * glm::dvec3(0.0, -std::sin(a), std::cos(a));
        request.camera.fovYDegrees = 30.0;
        request.relief.technique = Technique::DualDepth;
        request.relief.linearSteps = 64;
        request.relief.binarySteps = 8;
        request.picture.width = request.picture.height = kPicture;
        request.picture.output = RenderOutput::Depth;
        const Image depth = renderer.render(request);
        request.picture.output = RenderOutput::Uv;
        const Image uv = renderer.render(request);
        long compared = 0, agree = 0;
        std::vector<double> errors;
        for (int y = 0; y < kPicture; ++y) {
            for (int x = 0; x < kPicture; ++x) {
                const glm::dvec3 dir =
                    pixelRayDirection(request.camera, kPicture, kPicture, x + 0.5, y + 0.5);
                const double t = -request.camera.eye.z / dir.z;
                const glm::dvec2 entry = glm::dvec2(request.camera.eye) + t * glm::dvec2(dir);
                const glm::dvec2 exit = entry + glm::dvec2(dir) / -dir.z;  // at depth 1 (S = 1)
                if (std::min({entry.x, entry.y, exit.x, exit.y}) < 0.0 ||
                    std::max({entry.x, entry.y, exit.x, exit.y}) > 1.0)
                    continue;
                // Distance of the ray from the sphere's centre against the radius: skip the silhouette band.
                const glm::dvec3 o = request.camera.eye - kCentre;
                const double miss =
                    std::sqrt(std::max(glm::dot(o, o) - std::pow(glm::dot(o, dir), 2.0), 0.0));
                if (std::abs(miss - kRadius) < 1.5 / kSize) continue;
                const std::optional<double> expected = sphereDepth(request.camera.eye, dir);
                const bool hit = uv.at(x, y, 2) > 0.5f;
                ++compared;
                if (hit == expected.has_value()) ++agree;
                if (hit && expected)
                    errors.push_back(std::abs(static_cast<double>(depth.at(x, y)) - *expected));
            }
        }
        std::sort(errors.begin(), errors.end());
        const double p99 = errors.empty() ? 0.0 : errors[errors.size() * 99 / 100];
        std::printf("%4.0f deg: %ld pixels, hit/miss agreement %.3f %%, depth error p99 %.5f\n", angle,
                    compared, 100.0 * static_cast<double>(agree) / static_cast<double>(compared), p99);
        EXPECT_GT(compared, 2000);
        EXPECT_GE(static_cast<double>(agree) / static_cast<double>(compared), 0.999) << angle;
        // Binary search: 1 / (n 2^8) of the depth range; sampling: the sphere's chord sag over a texel,
        // r (1 - cos(asin(1 / (W r)))) ~ 1 / (2 W^2 r) near the middle, larger towards the outline.
        EXPECT_LE(p99, 0.01) << angle;
    }
}

TEST_F(DualDepthGl, TechniqueAndTextureMustMatch) {
    const GpuMaterial dual = uploadDualDepth(sphereTexture());
    ReliefTexture single;
    single.depth = Image(16, 16, 1, 0.5f);
    single.normal = normalsFromDepth(single.depth, 0.1);
    const GpuMaterial relief = uploadMaterial(single, 0.1);
    ReliefRenderer renderer;
    const GpuMesh quad = uploadMesh(makeBuiltinMesh("quad"));
    RenderRequest request;
    request.camera.eye = {0.5, -1.0, 1.5};
    request.camera.target = {0.5, 0.5, 0.0};
    request.picture.width = request.picture.height = 32;
    request.objects.push_back({&quad, glm::dmat4(1.0), &dual, glm::dvec3(0.8)});
    request.relief.technique = Technique::Relief;
    EXPECT_THROW(renderer.render(request), Error);
    request.objects[0].material = &relief;
    request.relief.technique = Technique::DualDepth;
    EXPECT_THROW(renderer.render(request), Error);
    DualDepthTexture bad = sphereTexture();
    bad.back = Image(8, 8, 1);
    EXPECT_THROW(uploadDualDepth(bad), Error);
}

}  // namespace
}  // namespace strata::gl
