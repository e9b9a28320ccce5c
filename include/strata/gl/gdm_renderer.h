// The GDM verification scene of CONVENTIONS §8 drawn with OpenGL 4.5: the paper's per-pixel algorithm
// (Wang et al. 2004, Sec. 3.2 and 4.2) in a fragment shader (shaders/gdm/gdm.frag.glsl), on the prism shell
// of the unit quad (strata/gdm/prism_shell.h). It is the GPU twin of emulateGdm (strata/gdm/gdm_trace.h):
// same scene, same lookups, same outputs, in float instead of double, so compareGdmScenes measures the two
// against each other and against the exact reference.
//
// What differs from emulateGdm: each prism is drawn on its own (its top and fins, back faces culled), and
// the exit point is the nearest other face by ray / triangle intersection with the prism's 8 triangles; a
// ray that leaves one prism without a hit is carried on by the fragment of the next prism's entry face, and
// the depth test keeps the nearest hit.
//
// Needs a current OpenGL 4.5 core context (HeadlessContext). Throws Error(InvalidInput) for what emulateGdm
// refuses and for an SVD that is not in the paper's layout, Error(Runtime) on a GL error.
#pragma once

#include "strata/environment/spherical_harmonics.h"
#include "strata/gdm/gdm.h"
#include "strata/gdm/gdm_rtv.h"
#include "strata/gdm/gdm_rtv_glossy.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/gdm/macro_transfer.h"
#include "strata/gdm/prism_shell.h"
#include "strata/mesh/mesh.h"
#include "strata/scene/camera.h"
#include "strata/scene/render_settings.h"

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace strata::gl {

GdmSceneImages renderGdmScene(const Gdm& gdm, const Camera& camera, glm::dvec3 light, int width, int height,
                              GdmDirectionLookup directions = GdmDirectionLookup::Nearest);
GdmSceneImages renderGdmScene(const GdmSvd& svd, const Camera& camera, glm::dvec3 light, int width,
                              int height, GdmDirectionLookup directions = GdmDirectionLookup::Nearest);

// The same algorithm on the prism shell of any mesh (buildPrismShell with `shell`; its height is the GDM's
// H): each prism corner's texture position is (tiling * uv of its mesh vertex, 0 at the base or H at the
// top), and the light direction in texture space is the world one in the surface's frame (T, B, N; the
// paper's approximation, GdmLightFrame). The
// outputs are those of GdmSceneImages, with u, v the tile coordinates modulo 1: the mask and uvw of
// CONVENTIONS §8 on a curved base. Throws as renderGdmScene, and as buildPrismShell for the mesh.
GdmSceneImages renderGdmMesh(const Gdm& gdm, const Mesh& mesh, const PrismShellOptions& shell,
                             const Camera& camera, glm::dvec3 light, int width, int height,
                             GdmDirectionLookup directions = GdmDirectionLookup::Nearest);
GdmSceneImages renderGdmMesh(const GdmSvd& svd, const Mesh& mesh, const PrismShellOptions& shell,
                             const Camera& camera, glm::dvec3 light, int width, int height,
                             GdmDirectionLookup directions = GdmDirectionLookup::Nearest);

// Which faces GdmRenderer::renderPrismIds draws.
enum class PrismFaces { Base, Shell };

// How a prism finds its hit along the segment T_in -> T_out (issue 18): the scene's GdmTechnique
// (render_settings.h), which this renderer implements as
//  Gdm     the paper's: one GDM lookup d(T_in, V), a hit if d < dt. Default.
//  Refine  not the paper's: with the signed distance volume (setDistance), sphere tracing on its
//          trilinear interpolation from T_in to T_out (steps of 0.9 times the distance, at least 0.1
//          voxel), the first zero crossing polished by 6 steps of regula falsi; the lookup's misses are
//          traced as its hits are. After 96 steps (a ray grazing a surface) the GDM lookup from there
//          answers. Without the distance volume: the lookup, then the occupancy volume's 0.5 crossing
//          within two voxels of it, sampled every quarter voxel (linear between samples); misses stay.
//  March   no GDM: the occupancy volume sampled every voxel (H / Nz) from T_in to T_out, the first 0.5
//          crossing (linear between samples). Its cost grows with the depth resolution: the baseline of
//          the paper's comparison with slice-based rendering.
using GdmTechnique = strata::GdmTechnique;

// How the shadow lookup takes the direction to the light into texture space (issue 18, "Local shadows"):
//  Tangent   the world direction in the surface's frame at the hit (the mesh's interpolated T, B, N,
//            normalised): (L.T, L.B, L.N), unscaled (the paper's approximation, Sec. 3.2). Default.
//  Jacobian  the world direction mapped by J^-1, J the prism's own Jacobian (gdmPrismJacobian); normalised.
using GdmLightFrame = strata::GdmLightFrame;

// The Jacobian of a prism's map from the isotropic texture frame (u, v, w H) to world, taken as affine: its
// columns are dP/du and dP/dv of the base triangle (from its corners' world positions `base` and tile
// coordinates `tile`, tiling * uv) and the mean of the three extrusions (top - base) divided by `height`
// (H). Where the flat quad's texture frame is world (tiling 1, T = H) it is the identity. Returns a matrix
// whose determinant is 0 for a triangle whose tile coordinates are degenerate (GdmRenderer then keeps the
// tangent-frame direction for that prism).
glm::dmat3 gdmPrismJacobian(const std::array<glm::dvec3, 3>& base, const std::array<glm::dvec3, 3>& top,
                            const std::array<glm::dvec2, 3>& tile, double height);

// Bytes of the storage and vertex buffers a GdmRenderer holds (the render target not counted).
struct GdmGpuMemory {
    std::size_t gdm = 0;      // the SVD's weight and eigen maps, or the raw GDM (floats)
    std::size_t volumes = 0;  // occupancy, linear albedo and signed distance (floats per voxel)
    std::size_t shell = 0;    // the prisms' faces, vertices and light frames
    // Environment lighting: the RTV's weight and basis maps and inside flags, the prisms' corners and the
    // per-vertex meso-scale lighting.
    std::size_t environment = 0;
    std::size_t total() const { return gdm + volumes + shell + environment; }
};

// The renderer behind the functions above, for drawing many pictures: the program is built once, the GDM
// and the mesh's shell are uploaded once (storage buffers), and each render() draws and reads back. Needs
// the context that made it to be current in every call, and when it is destroyed.
class GdmRenderer {
public:
    GdmRenderer();  // builds the program; throws Error(Runtime) if it does not compile or link
    ~GdmRenderer();
    GdmRenderer(const GdmRenderer&) = delete;
    GdmRenderer& operator=(const GdmRenderer&) = delete;

    // The GDM to draw: raw, or an SVD in the paper's layout. Throws Error(InvalidInput) as renderGdmScene.
    // Forgets the mesh (the shell's thickness and texture positions depend on H): set it again.
    void setGdm(const Gdm& gdm);
    void setGdm(const GdmSvd& svd);
    // The mesh whose prism shell is drawn (buildPrismShell with `shell`, its height the GDM's H). Throws
    // Error(InvalidInput) before setGdm, and as buildPrismShell.
    void setMesh(const Mesh& mesh, const PrismShellOptions& shell);

    // Refine and March need the occupancy volume (setVolumes); Refine uses the distance volume instead
    // where there is one (setDistance). The shadow is the GDM lookup's (towards the light in the frame of
    // setLightFrame), except Refine's on the distance volume: lit iff the distance's gradient faces the light
    // and sphere tracing from a quarter voxel off the surface towards it meets no zero crossing before it
    // leaves the slab 0 <= w <= 1 (the GDM lookup from where it stops after 96 steps).
    GdmSceneImages render(const Camera& camera, glm::dvec3 light, int width, int height,
                          GdmDirectionLookup directions = GdmDirectionLookup::Nearest,
                          GdmTechnique technique = GdmTechnique::Gdm);

    // The volumes for shading (GdmAsset's occupancy and, optional, sRGB albedo; x fastest, §8), for the
    // GDM set last. Throws Error(InvalidInput) before setGdm or for sizes that are not the GDM's voxels.
    void setVolumes(const std::vector<std::uint8_t>& occupancy, const std::vector<std::uint8_t>& albedo);
    // The signed distance volume (GdmAsset::distance, bakeGdmDistance: tile widths, negative inside, x
    // fastest) for the GDM set last; an empty one forgets it. Throws Error(InvalidInput) before setGdm or for
    // a size that is not the GDM's voxels. setGdm forgets it.
    void setDistance(const std::vector<float>& distance);
    // The same on a grid of its own, `size` voxels (Nx, Ny, Nz >= 1; §8 sampling in the same tile and H),
    // e.g. finer than the GDM's (bakeGdmDistance at those dims). Throws as above for a size that is not
    // distance.size().
    void setDistance(const std::vector<float>& distance, glm::ivec3 size);
    // The frame of the shadow lookup's light direction; Tangent until set. Kept across setGdm and setMesh.
    void setLightFrame(GdmLightFrame frame);
    // The shaded picture's Blinn-Phong terms, as the relief renderer's (render_settings.h: ambient times the
    // albedo; where lit, the light's colour times diffuse times the albedo plus specular); the light's
    // position is render's argument. Default Lighting{}. Kept across setGdm and setMesh. Throws as
    // validate(Lighting).
    void setLighting(const Lighting& lighting);
    // Whether a ray that comes through the base surface from below (from the mesh's inside, or from behind
    // an open mesh: the base is not solid, §8) enters the prism there, so that the far side of a mesh shows
    // through the holes of the near one, as the exact curved reference (gdm_mesh_reference.h) has it. The
    // paper's Sec. 3.2 rasterises each prism's "forward-facing sides, which may include prism fins and
    // triangles of the base surface". Default true; the §8 verification scene
    // (renderGdmScene, `strata gdm trace`) turns it off: there a ray that enters the box through its bottom
    // is a miss.
    void setBaseEntry(bool enabled);

    // Environment lighting with bi-scale radiance transfer (issue 19; Wang et al. 2004, Sec. 3.2 "Global
    // Illumination" and Sec. 4.2: "we first compute the per-vertex matrix/vector multiplication on the CPU to
    // obtain the incoming meso-scale radiance. Then the RTV vector for each pixel is reconstructed and dotted
    // with the interpolated incoming radiance vector"). With an RTV, the mesh's macro transfer and an
    // environment set, renderShaded adds to each hit
    //     albedo(hit) * sum over k of T_k(hit) L_k(hit), per channel,
    // T the RTV's transfer at the hit's texture point (gdmRtvTransferAt's lookup: trilinear, the corners
    // inside the solid left out) and L the meso-scale lighting there: the per-vertex lighting M_v * E (M_v
    // the vertex's macro transfer, E the environment's SH in world space) of the hit's prism's three corners,
    // interpolated with the barycentrics of the hit's (u, v) in the prism's footprint. The environment
    // replaces the ambient term; the point light adds its Blinn-Phong term with its local shadow as without
    // it (set its colour to 0 for the environment alone).
    //
    // The RTV of the GDM set last (same voxel grid): uncompressed (uploaded as rank 48 with the identity
    // basis) or its SVD (compressGdmRtv). Throws Error(InvalidInput) before setGdm or for another grid.
    // setGdm forgets it.
    void setRtv(const GdmRtv& rtv);
    void setRtv(const GdmRtvSvd& rtv);
    // A glossy term on top (gdm_rtv_glossy.h): the view-dependent RTV's SVD in the paper's layout (per SH
    // coefficient, rows the voxels, columns the views) and its specular coefficient; renderShaded adds
    //     specular * sum over k of G_k(hit, w_o) L_k
    // (white, not times the albedo), G reconstructed at the hit as gdmGlossyTransferAt does (the weights
    // trilinear over the voxel centres, the bases bilinear between the view directions), w_o the direction
    // from the hit towards the eye in the isotropic texture frame (minus the ray's texture-space direction).
    // Throws Error(InvalidInput) before setRtv, for another voxel grid, maps that do not match the rank, or
    // a specular that is not finite and >= 0. setRtv keeps it; setGdm forgets it; clearGlossyRtv drops it.
    void setGlossyRtv(const GdmGlossyRtvSvd& glossy, double specular);
    void clearGlossyRtv();
    // The macro transfer of the mesh set last (bakeMacroTransfer of the same mesh: one matrix per mesh
    // vertex). Throws Error(InvalidInput) before setMesh or for another vertex count. setMesh forgets it.
    void setMacroTransfer(const MacroTransfer& transfer);
    // The distant lighting, SH of the radiance in world space (Environment::sh(), rotated and scaled as the
    // caller likes): per vertex M_v times it, on the CPU, uploaded. Cheap: call it per frame to turn the
    // environment. Throws Error(InvalidInput) before setMacroTransfer.
    void setEnvironment(const ShColor& world);
    // Back to the ambient term: no environment lighting.
    void clearEnvironment();
    // Whether renderShaded draws with the environment (an RTV, a macro transfer and an environment set).
    bool hasEnvironment() const;

    // What the renderer holds on the GPU now.
    GdmGpuMemory gpuMemory() const;

    // A shaded picture: linear RGB and alpha 1 on a hit, all 0 elsewhere. The normal is the signed
    // distance's gradient where there is one (setDistance), else minus the occupancy's, at the hit (central
    // differences one voxel apart), taken to world space by the mesh's interpolated tangent frame; the albedo
    // is trilinear between the albedo volume's voxel centres (0.7 grey without one); Blinn-Phong from the
    // point light, with the local shadow of render(). Throws Error(InvalidInput) without the occupancy volume
    // (setVolumes).
    Image renderShaded(const Camera& camera, glm::dvec3 light, int width, int height,
                       GdmDirectionLookup directions = GdmDirectionLookup::Nearest,
                       GdmTechnique technique = GdmTechnique::Gdm);

    // The crack test's pictures: each pixel the id + 1 of the nearest prism face that covers it (0: none),
    // for the prisms' base faces (the mesh itself, no culling) or for the shell's faces as render() draws
    // them (tops and fins, back faces culled: the faces a ray enters a prism through). A ray that reaches
    // the base must enter the shell first, so a pixel covered by the base but by no entry face is a crack.
    Image renderPrismIds(const Camera& camera, int width, int height, PrismFaces faces);

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

}  // namespace strata::gl
