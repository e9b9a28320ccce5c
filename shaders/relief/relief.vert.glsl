#version 450 core
// Vertex stage of every surface program (relief-mapped or plain). Policarpo et al. 2005, Sec. 3: the
// mapping is done in tangent space, from "the texture coordinates and the tangent, normal and binormal
// vectors associated to the vertices of the model" (Sec. 5).
//
// Attributes (src/gl/gpu_mesh.cpp, uploadMesh): the Mesh's position, normal, uv and tangent
// (xyz + handedness w, B = w cross(N, T)), and uvLength = (|dP/du|, |dP/dv|), the object-space length of a
// unit of uv along T and B.

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
layout(location = 3) in vec4 aTangent;
layout(location = 4) in vec2 aUvLength;

// uModel, uNormalMatrix, uMirror, uViewProjection, uTiling: the per-draw block.
#include "shared/relief_uniforms.h"

out VertexData {
    vec3 worldPosition;
    vec3 normal;     // world, unit at the vertex
    vec3 tangent;    // world, unit, orthogonal to normal
    vec3 bitangent;  // world, unit
    vec2 tile;       // tile coordinates, tiling * uv
    // World length of one tile unit along T, B and N. T and B: the mesh's |dP/du|, |dP/dv| through the
    // model matrix, divided by the tiling. N: their geometric mean (a tile unit of depth is as long as the
    // square root of a tile's world area), so that S is a fraction of the tile's width as in CONVENTIONS §2.
    vec3 tileLength;
} vOut;

void main() {
    vec4 world = uModel * vec4(aPosition, 1.0);
    mat3 linear = mat3(uModel);
    vec3 n = normalize(uNormalMatrix * aNormal);
    vec3 t = linear * aTangent.xyz;
    float tLength = length(t);
    t = normalize(t - n * dot(n, t));  // Gram-Schmidt: a non-uniform scale may tilt T off the plane
    vec3 b = (aTangent.w * uMirror) * cross(n, t);
    // |dP/dv| through the model: the transformed bitangent direction of the object.
    vec3 objectB = aTangent.w * cross(aNormal, aTangent.xyz);
    float bLength = length(linear * objectB);

    vOut.worldPosition = world.xyz;
    vOut.normal = n;
    vOut.tangent = t;
    vOut.bitangent = b;
    vOut.tile = aUv * uTiling;
    // Kept above zero: a vertex whose uv mapping collapses (a pole) must not divide by zero downstream.
    vec2 tileLength = max(vec2(tLength * aUvLength.x, bLength * aUvLength.y) / uTiling, vec2(1e-6));
    vOut.tileLength = vec3(tileLength, sqrt(tileLength.x * tileLength.y));
    gl_Position = uViewProjection * world;
}
