// strata::gl::GpuMaterial: a relief material in GPU memory, and its three uploads: a baked relief texture
// (uploadMaterial), a live meta-relief's layers (uploadLiveMaterial) and a dual-depth texture
// (uploadDualDepth). The relief renderer (relief_renderer.h) draws them; docs/renderer.md describes how.
//
// Everything here needs a current OpenGL 4.5 core context (HeadlessContext, or the viewer's window), and a
// GpuMaterial must be destroyed while the context that made it is current.
//
// Conventions. Textures follow CONVENTIONS §1-§5: the packed relief texture (R, G = n.xy * 0.5 + 0.5,
// B = AO, A = d) is uploaded as RGBA16 with rows flipped (GL's row 0 is t = v = 0), full mipmaps, GL_REPEAT,
// trilinear + 16x anisotropic filtering; colour as SRGB8_ALPHA8 with mipmaps.
#pragma once

#include "strata/compose/compose.h"
#include "strata/image/image.h"
#include "strata/occlusion/meta_relief_ao.h"
#include "strata/relief/dual_depth.h"
#include "strata/relief/relief_texture.h"

#include "shared/relief_bindings.h"

#include <optional>
#include <span>
#include <vector>

namespace strata::gl {

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

// The most layers a live meta-relief has (the shader's sampler array; shaders/shared/relief_bindings.h).
inline constexpr int kMaxLiveLayers = shared::kMaxLiveLayers;

}  // namespace strata::gl
