// strata::gl::GpuMesh: a Mesh (strata/mesh/mesh.h) in GPU memory, as every surface program's vertex stage
// reads it (shaders/relief/relief.vert.glsl, attribute locations 0-4).
//
// Needs a current OpenGL 4.5 core context; a GpuMesh must be destroyed while the context that made it is
// current.
#pragma once

#include "strata/mesh/mesh.h"

namespace strata::gl {

// One vertex buffer (position, normal, uv, tangent, and the per-vertex world length of a unit of uv along T
// and B, see uploadMesh), one index buffer, one vertex array. Move-only.
class GpuMesh {
public:
    GpuMesh() = default;
    ~GpuMesh();
    GpuMesh(GpuMesh&& other) noexcept;
    GpuMesh& operator=(GpuMesh&& other) noexcept;
    GpuMesh(const GpuMesh&) = delete;
    GpuMesh& operator=(const GpuMesh&) = delete;

    int indexCount() const { return mIndexCount; }
    const Bounds& bounds() const { return mBounds; }  // object space
    // The largest object-space length of a unit of uv along T or B over the mesh (bounds the relief's
    // depth below the surface in object space: S * this / tiling).
    double maxUvLength() const { return mMaxUvLength; }
    unsigned vertexArray() const { return mVao; }

private:
    friend GpuMesh uploadMesh(const Mesh& mesh);
    unsigned mVao = 0;
    unsigned mVbo = 0;
    unsigned mIbo = 0;
    int mIndexCount = 0;
    Bounds mBounds;
    double mMaxUvLength = 1.0;
};

// Uploads a mesh: the Mesh attributes and, per vertex, the object-space length of one unit of uv along T
// and along B (uvLengths, strata/mesh/mesh.h). The shader turns these into the world size of a tile unit,
// so that a relief of depth S looks as deep (and casts shadows as long) as S tile widths
// (docs/renderer.md). Throws Error(InvalidInput) naming the mesh for an empty mesh, an index count that is
// not a multiple of 3, or an index out of range; Error(Runtime) on a GL error.
GpuMesh uploadMesh(const Mesh& mesh);

}  // namespace strata::gl
