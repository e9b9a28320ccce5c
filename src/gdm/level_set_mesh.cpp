#include "level_set_mesh.h"

#include <openvdb/tools/VolumeToMesh.h>

#include <mutex>

namespace strata::detail {

void initializeOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

SolidMesh meshLevelSet(const openvdb::FloatGrid& grid) {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(grid, points, triangles, quads, 0.0, 0.0);
    SolidMesh mesh;
    mesh.positions.reserve(points.size());
    for (const openvdb::Vec3s& p : points) mesh.positions.emplace_back(p.x(), p.y(), p.z());
    mesh.triangles.reserve(triangles.size() + 2 * quads.size());
    // Reversed: (a, c, b).
    for (const openvdb::Vec3I& t : triangles) mesh.triangles.push_back({t[0], t[2], t[1]});
    for (const openvdb::Vec4I& q : quads) {
        mesh.triangles.push_back({q[0], q[2], q[1]});
        mesh.triangles.push_back({q[0], q[3], q[2]});
    }
    return mesh;
}

}  // namespace strata::detail
