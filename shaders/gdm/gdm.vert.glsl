#version 450 core
// Vertex stage of the GDM program (Wang et al. 2004, Sec. 3.2 and 4.2): the faces of the prism shell
// (strata/gdm/prism_shell.h) that a ray can enter a prism through, its top, its fins and (turned
// over, for rays from below) its base, each vertex with
// its world position, its texture-space position in the isotropic frame (u, v, w H) of CONVENTIONS §8, and
// its prism.

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aTexture;
layout(location = 2) in uint aPrism;
layout(location = 3) in vec3 aTangent;    // world, unit: the mesh's T, B and N at the corner, for shading
layout(location = 4) in vec3 aBitangent;
layout(location = 5) in vec3 aNormal;

uniform mat4 uViewProjection;

out VertexData {
    vec3 worldPosition;
    vec3 texturePosition;
    flat uint prism;
    vec3 tangent;
    vec3 bitangent;
    vec3 normal;
} vOut;

void main() {
    vOut.worldPosition = aPosition;
    vOut.texturePosition = aTexture;
    vOut.prism = aPrism;
    vOut.tangent = aTangent;
    vOut.bitangent = aBitangent;
    vOut.normal = aNormal;
    gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
