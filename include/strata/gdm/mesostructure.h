// Procedural mesostructures (Wang et al. 2004, "Generalized Displacement Maps", Sec. 3.1; the built-ins after
// its Fig. 9 and 10): solids that repeat in u and v, defined by a distance bound in the tile's
// isotropic frame (u, v, z), z = w H (CONVENTIONS §8). One definition serves the voxelisation, the meshing
// (mesostructure_mesh.h), the preview and exact tracing (sphere tracing on the bound).
//
//   - distance(p): a bound on the signed Euclidean distance to the solid's surface in tile widths, negative
//     inside. It is 1-Lipschitz (|d(p) - d(q)| <= |p - q|), and |d(p)| never exceeds the true distance, so
//     that a sphere of radius |d(p)| around p does not cross the surface: sphere tracing with it is exact.
//     Where a part's exact distance is known (tori, cylinders, boxes, rigidly moved) it is that distance;
//     elsewhere it is a function with the same zero set divided by a bound on its gradient (each part says
//     which in mesostructure.cpp).
//   - Periodic: d(u + 1, v, z) = d(u, v + 1, z) = d(u, v, z) (to rounding: u and v are reduced modulo 1
//     first), for any real u, v. The solid lies within 0 <= z <= H.
//   - Albedo: an sRGB-encoded colour in [0, 1]^3, and an integer material id, at every point (those of the
//     part nearest to it).
//
// The solid is the union of parts (yarns, links, rods, scales, ridges); partDistance(k, p) is the bound for
// part k alone, and distance(p) = min over k. Parts may touch or fuse (the bark's ridges and its base) or be
// meant not to interpenetrate (the weave's yarns, the chain's links): the tests check those.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace strata {

// One part of a mesostructure, evaluated in its design frame: u, v in [0, 1) and z in [0, H0], H0 being
// the structure's default height (MesostructureInfo::defaultHeight).
struct MesostructurePart {
    std::string name;  // for messages and tests: "warp 0", "link 3"
    int material = 0;  // the material id of its points, >= 0
    // A 1-Lipschitz distance bound (see above), periodic in u and v, for u, v in [0, 1).
    std::function<double(const glm::dvec3&)> distance;
    // sRGB-encoded albedo in [0, 1]^3 at a point on or near the part.
    std::function<glm::dvec3(const glm::dvec3&)> albedo;
};

struct MesostructureSample {
    double distance = 0.0;   // distance(p)
    glm::dvec3 albedo{0.0};  // of the nearest part, sRGB-encoded, [0, 1]
    int material = 0;        // of the nearest part
    int part = 0;            // the nearest part's index
};

class Mesostructure {
public:
    // A structure designed for the height `designHeight` (> 0), shown at `height` (> 0): the parts are
    // stretched along z by k = height / designHeight, and the distance is scaled by min(1, k), which keeps it
    // a 1-Lipschitz bound (exact parts stay exact when k = 1). Throws Error(InvalidInput) naming `name` for
    // a height that is not finite and > 0, or for no parts.
    Mesostructure(std::string name, double designHeight, double height, std::vector<MesostructurePart> parts);

    const std::string& name() const { return mName; }
    double height() const { return mHeight; }  // H, tile widths
    int partCount() const { return static_cast<int>(mParts.size()); }
    const MesostructurePart& part(int k) const { return mParts[static_cast<std::size_t>(k)]; }

    // p = (u, v, z) with any real u, v and z; see the contract above.
    double distance(const glm::dvec3& p) const;
    double partDistance(int k, const glm::dvec3& p) const;
    MesostructureSample sample(const glm::dvec3& p) const;
    // The outward unit normal: the normalised central-difference gradient of distance() with step h.
    glm::dvec3 normal(const glm::dvec3& p, double h = 1e-5) const;

private:
    glm::dvec3 toDesign(const glm::dvec3& p) const;

    std::string mName;
    double mHeight;
    double mStretch;        // k = height / designHeight
    double mDistanceScale;  // min(1, k)
    std::vector<MesostructurePart> mParts;
};

struct MesostructureParams {
    double height = 0.0;     // H in tile widths, > 0; 0 means the structure's default height
    std::uint32_t seed = 1;  // the random choices of structures that have any (bark)
};

struct MesostructureInfo {
    std::string name;         // "weave"
    std::string description;  // one line, for `strata meso --list`
    double defaultHeight;     // H, tile widths
};

// The built-ins, in a stable order: weave, chain, grid, scales, bark (the paper's Fig. 9 and 10). Each keeps
// nothing above z = H (1 - 1.5 / 16): at 64 x 64 x 16 voxels the top voxel layer and a half stay empty.
const std::vector<MesostructureInfo>& mesostructureList();

// Throws Error(InvalidInput) for an unknown name (the message lists the known ones) or a height that is not
// finite and >= 0.
Mesostructure makeMesostructure(const std::string& name, const MesostructureParams& params = {});

}  // namespace strata
