// Built-in meshes: the Utah teapot, simple solids and the unit quad of CONVENTIONS §7.
//
// Every built-in is right-handed with +z up, has counter-clockwise outward triangles, unit normals, uvs and
// tangents with handedness (mesh.h), all analytic (not estimated from the triangles). docs/meshes.md shows
// the sizes and UV layouts:
//   teapot    Newell's 32 bicubic Bezier patches (teapot.h), spout along +x, handle along -x, standing on
//             z = 0, scaled so that its height is exactly 1 (x in [-0.952, 1.090], y in [-0.635, 0.635]).
//             Each patch is its own (n+1) x (n+1) grid of vertices with uv = the patch parameters (s, t) in
//             [0, 1]^2, so uv seams lie along every patch edge; vertex (i, j) of patch p (i along s, j along
//             t) is vertices[p * (n+1)^2 + j * (n+1) + i]. T is along dP/ds and B along dP/dt (w = +1).
//             Where a patch edge collapses to a point (knob top, bottom centre) N and T are the limits
//             (N = +z / -z there) and the zero-area triangles along it are left out: 32 * 2n^2 - 8n
//             triangles.
//   cube      the unit cube [-0.5, 0.5]^3; each face is an n x n grid with its own uvs in [0, 1]^2, laid out
//             so that a texture reads upright seen from outside (side faces: v up along +z; top: u = +x,
//             v = +y; bottom: u = +x, v = -y).
//   sphere    radius 0.5 at the origin (a UV sphere): u = longitude / 2 pi from +x counter-clockwise about
//             +z, v = 0 at the south pole to 1 at the north pole; 4n segments around, 2n from pole to pole.
//   torus     about +z, major radius 0.35 and tube radius 0.15 (1 across, 0.3 high): u around +z from +x,
//             v around the tube from the outer equator over the top; 4n x 4n segments.
//   cylinder  radius 0.5, z in [-0.5, 0.5], with caps: side u around +z from +x and v = z + 0.5 (4n
//             segments around, n along z); caps are fans with planar uvs (top: u = x + 0.5, v = y + 0.5;
//             bottom: u = x + 0.5, v = 0.5 - y, so both read upright from outside).
//   vase      open at both ends (no caps: the inside shows), a surface of revolution about +z, z in [-0.5,
//             0.5], radius r(t) = 0.22 + 0.16 sin(pi t) + 0.12 t^3 at t = z + 0.5 (a belly and a flared
//             neck): u around +z from +x, v = the profile's arc length from the bottom rim over the mean
//             circumference 2 pi mean(r) (2.21), so that a uv square is about square in world units (v in [0,
//             0.47]); radius at most 0.398; 4n segments around, 2n along.
//   patch     an open curved patch: a cylindrical arc of radius 0.6 about the y axis over 120 degrees (x in
//             [-0.52, 0.52], top at z = 0, its rims at z = -0.3), 1 wide in y; uv in world units, u = arc
//             length from the -x rim (in [0, 1.257]), v = y + 0.5; a 2n x 2n grid.
//   trunk     a tree trunk (the GDM paper's Fig. 10, bark), open at both ends (no caps), standing on z = 0,
//             z in [0, 2]: horizontal rings around an axis with a slight S-bend in x, x(z) = 0.05 sin(pi z);
//             radius r = R(z) (1 + L(theta, z)) at the angle theta about +z from +x, with
//             R(z) = (1 + 0.09 (1 - z)) / pi * (1 + 0.3 exp(-z / 0.12)) (a mild taper from 0.347 to 0.290,
//             1 / pi at z = 1, and a root flare to 0.451 at the ground) and low lumps
//             L = 0.02 cos(3 theta + 1.1 z) + 0.015 sin(7 theta - 2.3 z) + 0.06 exp(-z / 0.25) cos(5 theta)
//             (the last: five root lobes). x in [-0.429, 0.488], y in [-0.464, 0.458]. uv about in world
//             units: u = theta / pi, the arc length on the circle of circumference 2 (radius 1 / pi, about
//             the trunk's at z = 1), u in [0, 2] with the seam's vertices doubled at u = 0 and u = 2 (so a
//             tiling T with 2T a whole number wraps without a seam); v = the integral from 0 to z of
//             sqrt(1 + x'^2 + R'^2) / (pi R) dz: height along the trunk in the same local scale as u (one
//             unit of u or v is pi R(z) long), so a uv square stays square (conformal but for the lumps and
//             the lean), v in [0, 2.007]. Above z = 0.5 a uv unit is 0.88 to 1.09 long; the flare
//             stretches u and v together, up to 1.57 at the ground. 4n segments around, 4n along.
//   plane     the square [-1, 1]^2 in z = 0 facing +z, uv = ((x + 1) / 2, (y + 1) / 2), an n x n grid.
//   quad      exactly the unit quad of CONVENTIONS §7: x, y in [0, 1], z = 0, uv = (x, y), T = +x, B = +y,
//             N = +z, four vertices (0,0), (1,0), (1,1), (0,1) and two triangles {0,1,2}, {0,2,3}. Ignores
//             the tessellation.
#pragma once

#include "strata/mesh/mesh.h"

#include <string>
#include <vector>

namespace strata {

struct BuiltinMeshParams {
    // Segments per patch edge (teapot), per quarter turn (sphere, torus, cylinder, vase, trunk), per edge
    // (cube faces, plane), per half edge (patch) or per half unit of height (trunk). Range [1, 256]; default
    // 16: the teapot is then 32 * 17^2 = 9248 vertices and 16256 triangles, smooth in silhouette at 1280x720.
    // The quad ignores it.
    int tessellation = 16;
};

// The names makeBuiltinMesh accepts, in a fixed order: teapot, cube, sphere, torus, cylinder, vase, patch,
// trunk, plane, quad.
std::vector<std::string> builtinMeshList();

// Builds a built-in mesh (see the list above); Mesh::name is the name.
// Throws Error(InvalidInput) for an unknown name (the message lists the known ones) or a tessellation
// outside [1, 256].
Mesh makeBuiltinMesh(const std::string& name, const BuiltinMeshParams& params = {});

}  // namespace strata
