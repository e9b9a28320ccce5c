// Internal to strata::gdm: the warped-solid scene of a mesostructure in the prism shell of a mesh, and the
// walk of a ray through it, as the exact reference on curved bases defines them (gdm_mesh_reference.h:
// geometry, cut faces, seams, the inside test at boundary points). Shared by that reference
// (gdm_mesh_reference.cpp) and the path tracer on curved bases (gdm_mesh_path_trace.cpp), so that both see
// the same geometry and the same first hits.
#pragma once

#include "strata/gdm/gdm_mesh_reference.h"
#include "strata/gdm/prism_shell.h"
#include "strata/gdm/solid_mesh.h"
#include "strata/mesh/mesh.h"

#include "periodic_scene.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace strata::detail {

// What a flat triangle of the warped scene is: a piece of a warped solid face, or of the shell's boundary
// (a prism's top, its base, i.e. the mesh's own triangle, or a fin that is a face: rim or seam).
enum class WarpedFaceKind : std::uint8_t { Solid, Top, Base, Fin };

// The warped scene's flat triangles: per triangle what a hit on it means.
struct WarpedFace {
    std::array<glm::dvec3, 3> texture;  // (u, v, z) at the corners, tile coordinates (not wrapped)
    glm::vec3 normal;                   // outward, world, unit
    glm::vec3 textureNormal;            // outward, texture space, unit (boundary faces: for the nudge)
    WarpedFaceKind kind;
    std::uint32_t prism = 0;  // the prism (PrismShell::prisms index) whose volume it belongs to
};

// The warped scene, ready for rays. Movable; Embree's errors go to the EmbreeErrors it was built with,
// which must outlive it.
struct WarpedScene {
    PeriodicScene periodic;  // the unwarped periodic solid, for the inside test at boundary points
    GeometryHandle geometry;
    SceneHandle scene;  // the flat triangles, watertight, with the crossed-face filter
    std::vector<WarpedFace> faces;
    double height = 0.0;     // H, tile widths
    double thickness = 0.0;  // T, world units
    // Per prism: the unit world normal of its base triangle (the mesh's own triangle), pointing away from
    // the mesh into the shell; zero for a prism left out (no footprint).
    std::vector<glm::dvec3> baseNormals;
};

// Builds the scene of gdm_mesh_reference.h (the shell's height is the solid's), filling the counts of
// `stats` that describe the geometry (all but exitFaceCrossings and hitsFromBelow). The caller has checked
// the solid; throws what buildPrismShell throws for the mesh, and Error(Runtime) naming `what` if Embree
// fails.
WarpedScene buildWarpedScene(const SolidMesh& solid, const Mesh& mesh, const PrismShellOptions& shell,
                             double chordTolerance, const std::string& what, EmbreeErrors& errors,
                             GdmMeshReferenceStats& stats);

struct WarpedCrossing {
    bool found = false;
    double t = 0.0;
    glm::dvec3 texture{0.0};  // tile coordinates, not wrapped
    glm::dvec3 normal{0.0};   // outward, world, unit
    WarpedFaceKind kind = WarpedFaceKind::Solid;
    std::uint32_t prism = 0;
    bool exitFace = false;   // met a solid face from inside first
    bool fromBelow = false;  // entered the shell through a base (from inside the mesh) before its hit
};

// How a ray walks the warped scene.
struct WarpedRayRule {
    // Stop at a solid face met either way (the shadow's blockers; a path's next vertex), not only at one
    // the ray enters the solid through.
    bool anySolidFace = false;
    // false: a ray that enters the shell through a base ends there, as a miss (GdmMeshReferenceOptions).
    bool throughBase = true;
    // true: a base met either way stops the ray (found, kind Base): the mesh as an opaque occluder.
    bool baseBlocks = false;
};

// The first point of the ray (origin, direction), within [0, tFar), that lies in the warped solid inside
// the shell: an entered solid face, or a boundary point entered inside the solid (gdm_mesh_reference.h),
// under `rule`.
WarpedCrossing firstWarpedHit(const WarpedScene& warped, const glm::dvec3& origin,
                              const glm::dvec3& direction, double tFar, const WarpedRayRule& rule);

}  // namespace strata::detail
