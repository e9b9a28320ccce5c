// strata::gl::ReliefRenderer: relief mapping on arbitrary polygonal surfaces in OpenGL 4.5 core
// (Policarpo, Oliveira, Comba 2005, "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces", Sec. 3 and
// the appendix's Cg shader), with the meta-relief paper's texture-space AO (Limberger et al. 2015, Sec. IV).
// docs/renderer.md describes the techniques, shader variants, texture-to-world scale and measured accuracy.
//
// Everything here needs a current OpenGL 4.5 core context (HeadlessContext, or the viewer's window), and
// GPU objects must be destroyed while the context that made them is current.
//
// Conventions. Textures follow CONVENTIONS §1-§5: the packed relief texture (R, G = n.xy * 0.5 + 0.5,
// B = AO, A = d) is uploaded as RGBA16 with rows flipped (GL's row 0 is t = v = 0), full mipmaps, GL_REPEAT,
// trilinear + 16x anisotropic filtering; colour as SRGB8_ALPHA8 with mipmaps. Pictures come back with
// row 0 = top (CONVENTIONS §7).
#pragma once

#include "strata/compose/compose.h"
#include "strata/image/image.h"
#include "strata/mesh/mesh.h"
#include "strata/occlusion/meta_relief_ao.h"
#include "strata/relief/dual_depth.h"
#include "strata/relief/relief_texture.h"
#include "strata/scene/camera.h"
#include "strata/scene/render_settings.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace strata::gl {

struct ProgramVariant;

// A mesh in GPU memory: one vertex buffer (position, normal, uv, tangent, and the per-vertex world length
// of a unit of uv along T and B, see uploadMesh), one index buffer, one vertex array. Move-only.
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

// Uploads a mesh. Besides the Mesh attributes it computes, per vertex, the object-space length of one unit
// of uv along T and along B (|dP/du|, |dP/dv|: the area-weighted mean over the triangles around the vertex;
// 1 where the uv mapping is degenerate). The shader turns these into the world size of a tile unit, so that
// a relief of depth S looks as deep (and casts shadows as long) as S tile widths (docs/renderer.md).
// Throws Error(InvalidInput) naming the mesh for an empty mesh, an index count that is not a multiple of 3,
// or an index out of range; Error(Runtime) on a GL error.
GpuMesh uploadMesh(const Mesh& mesh);

// One layer of a live meta-relief in GPU memory (uploadLiveMaterial).
struct GpuLayer {
    unsigned texture = 0;       // packed (CONVENTIONS §5 layout): n.xy, the layer's AO, d
    unsigned color = 0;         // the layer's colour (SRGB8_ALPHA8), 0 if it has none
    double tiling = 1.0;        // t_i
    double weightDepth = 1.0;   // w_d,i (not normalised)
    double weightNormal = 1.0;  // w_n,i (not normalised)
    double aoDepthScale = 0.0;  // S_i its AO was baked at; 0 = no AO (texture B = 1)
    double normalScale = 1.0;   // consistent normals: the S_L its normals were derived from depth at
    double depthMin = 0.0;      // the range of its depth as uploaded (every mip level stays within it)
    double depthMax = 1.0;
    int width = 0;
    int height = 0;
};

// A relief material in GPU memory: the packed relief texture (CONVENTIONS §5), the colour texture (1x1
// white if the texture has none) and what the shader needs to know about them; or, for a live meta-relief
// (uploadLiveMaterial), its layers. Move-only.
class GpuMaterial {
public:
    GpuMaterial() = default;
    ~GpuMaterial();
    GpuMaterial(GpuMaterial&& other) noexcept;
    GpuMaterial& operator=(GpuMaterial&& other) noexcept;
    GpuMaterial(const GpuMaterial&) = delete;
    GpuMaterial& operator=(const GpuMaterial&) = delete;

    // Live meta-relief (Limberger et al. 2015, Sec. III-A): the layers are combined per fragment.
    bool isLive() const { return !mLayers.empty(); }
    const std::vector<GpuLayer>& layers() const { return mLayers; }
    NormalMode normalMode() const { return mNormalMode; }
    // How the live AO is made: nullopt none; Multiply / Min the layers' maps per fragment; Exact the
    // composed AO map (setComposedAo).
    std::optional<MetaAoMode> liveAo() const { return mLiveAo; }
    int colorLayer() const { return mColorLayer; }  // -1: none
    // Changes a layer's tiling and weights: nothing is re-uploaded or re-baked (the layers' AO maps are
    // rescaled per fragment by paper Eq. 4-6; an Exact AO map is the caller's to re-bake). Throws
    // Error(InvalidInput) naming the layer for an index out of range, tiling not > 0, a negative or
    // non-finite weight, or weights that leave no depth (or, in paper normals, no normal) weight at all.
    void setLayer(int index, double tiling, double weightDepth, double weightNormal);
    // The AO map of the composed depth (1 channel, any size, tiling 1), valid at depth scale aoDepthScale:
    // uploaded (replacing the previous one) and used by a live material whose liveAo() is Exact.
    void setComposedAo(const Image& ao, double aoDepthScale);
    unsigned composedAoTexture() const { return mComposedAo; }
    // The maximum mipmap of the depth (Technique::MaxMip): R16, level 0 the highest point (smallest d) of
    // each bilinear cell, level k of 2^k x 2^k cells. 0 when the depth map's sides are not powers of two
    // (or for a live material): maxmip then refuses to render.
    unsigned maxMipTexture() const { return mMaxMip; }
    // A dual-depth texture (uploadDualDepth): its packed texture holds (nx, ny, front, back), and only
    // Technique::DualDepth draws it.
    bool isDualDepth() const { return mDualDepth; }
    int maxMipLevels() const { return mMaxMipLevels; }
    // The cone map of the depth (Technique::Cone; strata/relief/cone_map.h and shaders/relief/cone.glsl):
    // RG16 per cell, (the cell's highest point, sqrt(ratio / coneMaxRatio())), the ratio rounded down. Made
    // from the depth exactly as uploaded (16-bit) on the first call, with the GL context current: the
    // generator's cost (docs/renderer.md) is paid only by materials drawn with cone. 0 for a live or a
    // dual-depth material.
    unsigned coneTexture() const;
    double coneMaxRatio() const { return mConeMaxRatio; }

    double depthScale() const { return mDepthScale; }      // S the normal map is valid for
    double aoDepthScale() const { return mAoDepthScale; }  // S the AO channel is valid for
    bool hasAo() const { return mHasAo; }
    bool hasColor() const { return mHasColor; }
    int width() const { return mWidth; }  // of the relief texture
    int height() const { return mHeight; }
    unsigned reliefTexture() const { return mRelief; }
    unsigned colorTexture() const { return mColor; }

private:
    friend GpuMaterial uploadMaterial(const ReliefTexture& texture, double aoDepthScale);
    friend GpuMaterial uploadDualDepth(const DualDepthTexture& texture);
    friend GpuMaterial uploadLiveMaterial(std::span<const CompositionLayer> layers,
                                          const ComposeParams& compose, std::optional<MetaAoMode> ao,
                                          const AoParams& aoParams, std::span<const Image> layerAo);
    void release();
    unsigned mRelief = 0;
    unsigned mColor = 0;
    std::vector<GpuLayer> mLayers;
    NormalMode mNormalMode = NormalMode::Paper;
    std::optional<MetaAoMode> mLiveAo;
    int mColorLayer = -1;
    unsigned mComposedAo = 0;
    unsigned mMaxMip = 0;
    mutable Image mConeDepth;    // the uploaded depth (16-bit values), until coneTexture() is made
    mutable unsigned mCone = 0;  // made on first use (coneTexture)
    mutable double mConeMaxRatio = 0.0;
    bool mDualDepth = false;
    int mMaxMipLevels = 0;
    double mDepthScale = kDefaultDepthScale;
    double mAoDepthScale = kDefaultDepthScale;
    bool mHasAo = false;
    bool mHasColor = false;
    int mWidth = 0;
    int mHeight = 0;
};

// `texture`: depth + normal (+ colour, + ao). aoDepthScale: the depth scale the AO map is valid at (usually
// texture.depthScale; the caller re-bakes for AoRescale::Exact and passes the render's S).
// Throws Error(InvalidInput) for a texture without depth or normals, maps of the wrong channel count, or a
// non-positive aoDepthScale; Error(Runtime) on a GL error.
GpuMaterial uploadMaterial(const ReliefTexture& texture, double aoDepthScale);

// A live meta-relief (Limberger et al. 2015, Sec. III-A and V): every layer uploaded as its own packed
// texture at its own resolution, combined by the shader per fragment (Eq. 2 for the depth the searches see;
// Eq. 1 or the composed depth's own normal, compose.normals; the colour of layer compose.colorFrom at that
// layer's tiling). Fractional tilings have no seam and weights change with GpuMaterial::setLayer, without a
// re-bake. compose.depthScale is the material's S; compose.resolution is not used.
// AO (`ao`): nullopt none; Multiply / Min: each layer's AO baked now at its share of the depth,
// S_i = S (w_d,i / W) t_i (metaReliefLayerAoParams, with aoParams' method, directions and radius), combined
// per fragment and rescaled to the current weights by Eq. 4-6; Exact: the AO of the composed depth, which the
// caller bakes and passes with setComposedAo (until then AO is 1).
// Throws Error(InvalidInput) like compose() for bad layers or weights and for more than kMaxLiveLayers
// layers; Error(Runtime) on a GL error.
GpuMaterial uploadLiveMaterial(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                               std::optional<MetaAoMode> ao, const AoParams& aoParams);
// The same with the layers' AO maps for Multiply / Min baked by the caller (e.g. on a worker thread, so
// that the GL thread only uploads): layerAo[i] is bakeAo(layers[i].texture.depth, *liveLayerAoParams[i])
// with liveLayerAoParams = metaReliefLayerAoParams(layers, compose, aoParams), and an empty Image where
// that is nullopt. Throws Error(InvalidInput) as above, and for a layerAo of another size than `layers` or
// a map of another size than its layer's depth.
GpuMaterial uploadLiveMaterial(std::span<const CompositionLayer> layers, const ComposeParams& compose,
                               std::optional<MetaAoMode> ao, const AoParams& aoParams,
                               std::span<const Image> layerAo);

// A dual-depth texture (Policarpo et al. 2005, Sec. 4; strata/relief/dual_depth.h) for Technique::DualDepth:
// RGBA16 (nx * 0.5 + 0.5, ny * 0.5 + 0.5, front, back) with mipmaps, white colour, no AO, S = its depth
// scale. Throws Error(InvalidInput) for maps of other channel counts or sizes, or a depth scale that is not >
// 0.
GpuMaterial uploadDualDepth(const DualDepthTexture& texture);

// The most layers a live meta-relief has (the shader's sampler array).
inline constexpr int kMaxLiveLayers = 8;

struct SceneObject {
    const GpuMesh* mesh = nullptr;
    glm::dmat4 model{1.0};                  // object -> world
    const GpuMaterial* material = nullptr;  // null: plain Blinn-Phong surface of `color`
    glm::dvec3 color{0.8};                  // sRGB-encoded albedo of a plain surface, [0, 1]
};

struct RenderRequest {
    std::vector<SceneObject> objects;
    Camera camera;
    ReliefSettings relief;  // the same settings for every object with a material
    Lighting lighting;
    PictureSettings picture;
};

class ReliefRenderer {
public:
    // Needs a current GL 4.5 core context; compiles programs lazily per variant and caches them.
    ReliefRenderer();
    ~ReliefRenderer();
    ReliefRenderer(const ReliefRenderer&) = delete;
    ReliefRenderer& operator=(const ReliefRenderer&) = delete;

    // Renders into framebuffers of its own and reads the picture back. Shaded: 3 channels, sRGB-encoded
    // [0, 1], supersampled on a k x k grid per pixel (k = round(sqrt(picture.samples))). Uv: 3ch (u, v,
    // hit). Shadow, Depth: 1ch.
    // The debug outputs are 1 sample, float, not tone mapped (CONVENTIONS §7). Row 0 = top.
    // Throws Error(InvalidInput) for invalid settings or camera, or an object without a mesh;
    // Error(Runtime) for a GL error or a shader that fails to build.
    Image render(const RenderRequest& request);

    // Renders into the currently bound framebuffer with the given viewport (for the viewer); shaded only
    // (request.picture.output and size are ignored). Clears colour and depth to the background; writes
    // sRGB-encoded values (the caller must not enable GL_FRAMEBUFFER_SRGB). Same errors as render().
    void draw(const RenderRequest& request, int viewportWidth, int viewportHeight);

    // Builds (or finds in the cache) the program of a variant; throws like buildProgram. For tests and for
    // warming the cache.
    void prepare(const ProgramVariant& variant);

private:
    struct Impl;
    std::unique_ptr<Impl> mImpl;
};

}  // namespace strata::gl
