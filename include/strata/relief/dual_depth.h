// Dual-depth relief textures (Policarpo, Oliveira, Comba 2005, Section 4): a closed object sampled
// orthographically along one axis into two depth layers, its front and its back surface, so that one quad
// can stand in for the object (an impostor) without the "skins" a single depth layer draws between the
// object and the floor of its depth range.
//
// Sampling. Looking down the chosen axis (from its + side: for z, from above), the footprint is the square
// of side L = the larger of the mesh bounds' two other extents, centred on the bounds; texel (i, j)
// (row 0 at the top, as images are, so v grows with the second axis) samples the line through its centre.
// front d = (max_axis - a_first) / E and back d = (max_axis - a_last) / E, E = the bounds' extent along the
// axis and a_first, a_last the axis coordinates of the highest and lowest surface points on the line: d = 0
// at the top of the bounds, 1 at the bottom (CONVENTIONS §2). A line that misses the mesh stores front = 1,
// back = 0 (front > back: never inside). The depth scale is S = E / L tile widths, so the quad of side L
// shows the object at its true proportions. Tile frame: T = the first other axis, B = the second, N = the
// axis (for z: x, y, z; for x: y, z, x; for y: z, x, y).
//
// Normals: the mesh's interpolated vertex normal at the front point, in that tile frame, turned to face
// up (+N) where it does not by making its N component non-negative (packed.png keeps nx, ny and a reader
// recovers nz = sqrt(1 - nx^2 - ny^2) >= 0, so mirroring is what survives the file); lines that miss store
// (0, 0, 1). A texel centre on a triangle edge counts as inside (the test is inclusive).
//
// Files (a directory): packed.png, 16-bit RGBA = (nx * 0.5 + 0.5, ny * 0.5 + 0.5, front, back), and the
// sidecar strata.json with "format": "strata.dual-depth", "version": 1, "width", "height", "depth_scale",
// "axis" and "source" (the mesh).
#pragma once

#include "strata/image/image.h"
#include "strata/mesh/mesh.h"

#include <filesystem>
#include <string>
#include <vector>

namespace strata {

inline constexpr const char* kDualDepthFormat = "strata.dual-depth";

enum class Axis { X, Y, Z };
const char* toString(Axis axis);
// "x" | "y" | "z"; throws Error(InvalidInput) for anything else.
Axis parseAxis(const std::string& text);

struct DualDepthTexture {
    Image front;              // 1 channel, d of the front surface; 1 where the line misses
    Image back;               // 1 channel, d of the back surface; 0 where the line misses
    Image normal;             // 3 channels, unit front normals in the tile frame (see the top of this file)
    double depthScale = 1.0;  // S = E / L, tile widths
    Axis axis = Axis::Z;
};

// Samples `mesh` as described at the top of this file, size x size texels. Throws Error(InvalidInput) for
// a size outside [1, Image::kMaxDimension], a mesh without triangles or with a flat extent along the axis
// or across it.
DualDepthTexture makeDualDepth(const Mesh& mesh, Axis axis, int size);

// Writes packed.png and strata.json into `dir` (created if missing), each through a temporary file and a
// rename; returns the files written. Throws Error(Io) naming the file.
std::vector<std::filesystem::path> writeDualDepth(const std::filesystem::path& dir,
                                                  const DualDepthTexture& texture, const std::string& source);
// Reads a directory (or its strata.json) written by writeDualDepth. Throws Error(Io) for a missing file,
// Error(InvalidInput) naming the file and key for a sidecar of another format or a packed.png that is not
// 4 channels of the recorded size; Error(Unsupported) for a "version" other than 1.
DualDepthTexture readDualDepth(const std::filesystem::path& path);
// Whether `path` is such a directory (or its sidecar): its strata.json says "format": "strata.dual-depth".
bool isDualDepth(const std::filesystem::path& path);

}  // namespace strata
