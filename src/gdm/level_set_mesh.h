// Private to the gdm module: OpenVDB level sets to SolidMesh, shared by meshMesostructure and readSolidVdb.
#pragma once

#include "strata/gdm/solid_mesh.h"

#include <openvdb/openvdb.h>

namespace strata::detail {

// openvdb::initialize(), once per process (grid types must be registered before any file is read).
void initializeOpenVdb();

// The zero isosurface of a level set (negative inside) in its world space: volumeToMesh with adaptivity 0,
// quads split into two triangles, all of them reversed so that they are counter-clockwise seen from outside
// (volumeToMesh's polygons face into the negative region). Positions as OpenVDB gives them.
SolidMesh meshLevelSet(const openvdb::FloatGrid& grid);

}  // namespace strata::detail
