#include "strata/gl/relief_renderer.h"

#include "relief_program.h"
#include "render_target.h"
#include "texture_upload.h"

#include "shared/relief_bindings.h"
#include "shared/relief_uniforms.h"
#include "strata/core/error.h"
#include "strata/gl/gl_error.h"
#include "strata/gl/gpu_material.h"
#include "strata/gl/gpu_mesh.h"
#include "strata/image/srgb.h"

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace strata::gl {

namespace {

glm::mat4 toFloat(const glm::dmat4& m) {
    return glm::mat4(m);
}

}  // namespace

struct ReliefRenderer::Impl {
    std::map<ProgramVariant, Program> programs;
    GLuint flatRelief = 0;  // 1x1 packed texel of a flat relief (n = +z, AO 1, d 0), for plain objects
    GLuint white = 0;       // 1x1 white colour
    // For the debug outputs: the base level's bilinear, wrap-around height field of CONVENTIONS §1 and
    // nothing else. The shader reads it with textureLod(..., 0), but an explicit LOD does not switch off
    // anisotropic filtering everywhere (llvmpipe keeps filtering along a footprint of its own and moved
    // uv hits by several texels), so these outputs bind a sampler object without mipmaps or anisotropy.
    GLuint baseLevelSampler = 0;
    // For the shaded output's searches: trilinear mip mapping (paper Sec. 5) without anisotropy. The final
    // colour, normal and AO fetches keep the textures' own 16x anisotropic filtering (kColorUnit,
    // kReliefShadeUnit). An anisotropic fetch in every search step costs up to 16 trilinear probes each (on
    // llvmpipe, which does them in software, an order of magnitude per frame: docs/renderer.md), and on a
    // GPU it only blurs a height field whose crossing the binary search locates anyway.
    GLuint searchSampler = 0;
    // The per-draw uniform block (shared/relief_uniforms.h), rewritten before every draw.
    GLuint uniformBuffer = 0;
    RenderTarget target;

    Impl() {
        const std::vector<std::uint16_t> flat = {32768, 32768, 65535, 0};
        flatRelief = makeTexture(GL_RGBA16, 1, 1, GL_RGBA, GL_UNSIGNED_SHORT, flat, 4);
        const std::vector<std::uint8_t> whiteTexel = {255, 255, 255, 255};
        white = makeTexture(GL_SRGB8_ALPHA8, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, whiteTexel, 4);
        glCreateSamplers(1, &baseLevelSampler);
        glSamplerParameteri(baseLevelSampler, GL_TEXTURE_WRAP_S, GL_REPEAT);
        glSamplerParameteri(baseLevelSampler, GL_TEXTURE_WRAP_T, GL_REPEAT);
        glSamplerParameteri(baseLevelSampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glSamplerParameteri(baseLevelSampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glCreateSamplers(1, &searchSampler);
        glSamplerParameteri(searchSampler, GL_TEXTURE_WRAP_S, GL_REPEAT);
        glSamplerParameteri(searchSampler, GL_TEXTURE_WRAP_T, GL_REPEAT);
        glSamplerParameteri(searchSampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glSamplerParameteri(searchSampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glCreateBuffers(1, &uniformBuffer);
        glNamedBufferStorage(uniformBuffer, sizeof(shared::ReliefUniforms), nullptr, GL_DYNAMIC_STORAGE_BIT);
        checkGl("ReliefRenderer: creating default textures");
    }

    ~Impl() {
        glDeleteTextures(1, &flatRelief);
        glDeleteTextures(1, &white);
        glDeleteSamplers(1, &baseLevelSampler);
        glDeleteSamplers(1, &searchSampler);
        glDeleteBuffers(1, &uniformBuffer);
    }

    const Program& program(const ProgramVariant& variant) {
        const ProgramVariant key = canonical(variant);
        auto it = programs.find(key);
        if (it == programs.end()) it = programs.emplace(key, buildVariantProgram(key)).first;
        return it->second;
    }

    void drawScene(const RenderRequest& request, int width, int height, bool encodeSrgb,
                   const glm::vec4& clearColor);
    static void setLiveUniforms(shared::ReliefUniforms& uniforms, const GpuMaterial& material,
                                double depthScale, const ReliefSettings& relief);
};

namespace {

void validateRequest(const RenderRequest& request) {
    validate(request.relief);
    validate(request.lighting);
    validate(request.picture);
    validate(GdmSettings{}, request.picture);  // a relief output: uvw and mask are a GDM render's
    validateCamera(request.camera);
    for (std::size_t i = 0; i < request.objects.size(); ++i) {
        if (request.objects[i].mesh == nullptr) {
            throw Error(ErrorKind::InvalidInput,
                        "render request: object " + std::to_string(i) + " has no mesh");
        }
        const GpuMaterial* material = request.objects[i].material;
        const bool dualTechnique = request.relief.technique == Technique::DualDepth;
        if (material != nullptr && material->isDualDepth() != dualTechnique) {
            throw Error(
                ErrorKind::InvalidInput,
                "render request: object " + std::to_string(i) +
                    (dualTechnique ? ": technique dual-depth needs a dual-depth texture (strata dual-depth)"
                                   : ": a dual-depth texture draws only with technique dual-depth"));
        }
        if (request.relief.technique == Technique::Cone && material != nullptr && material->isLive()) {
            throw Error(ErrorKind::InvalidInput, "render request: object " + std::to_string(i) +
                                                     ": cone needs a baked material (--meta baked)");
        }
        if (request.relief.technique == Technique::MaxMip && material != nullptr) {
            if (material->isLive()) {
                throw Error(ErrorKind::InvalidInput, "render request: object " + std::to_string(i) +
                                                         ": maxmip needs a baked material (--meta baked)");
            }
            if (material->maxMipTexture() == 0) {
                throw Error(ErrorKind::InvalidInput, "render request: object " + std::to_string(i) +
                                                         ": maxmip needs a depth map whose "
                                                         "sides are powers of two, got " +
                                                         std::to_string(material->width()) + "x" +
                                                         std::to_string(material->height()));
            }
        }
    }
}

// Near and far planes from the scene's bounds (each object's box grown by the deepest relief it can show,
// in object space), measured along the view direction, with a small margin. A camera inside the scene gets
// near = far / 10^4.
std::pair<double, double> clipPlanes(const RenderRequest& request) {
    const CameraFrame frame = cameraFrame(request.camera);
    double nearest = std::numeric_limits<double>::infinity();
    double farthest = -std::numeric_limits<double>::infinity();
    for (const SceneObject& object : request.objects) {
        const Bounds& bounds = object.mesh->bounds();
        double grow = 0.0;
        if (object.material != nullptr) {
            const double scale = request.relief.depthScale.value_or(object.material->depthScale());
            grow = scale * object.mesh->maxUvLength() / request.relief.tiling;
        }
        const glm::dvec3 lo = glm::dvec3(bounds.min) - grow;
        const glm::dvec3 hi = glm::dvec3(bounds.max) + grow;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y,
                               (corner & 4) ? hi.z : lo.z);
            const glm::dvec3 world = glm::dvec3(object.model * glm::dvec4(p, 1.0));
            const double distance = glm::dot(world - request.camera.eye, frame.forward);
            nearest = std::min(nearest, distance);
            farthest = std::max(farthest, distance);
        }
    }
    if (!(farthest > 0.0)) return {0.01, 1.0};  // nothing in front of the camera
    // The relief repeats under neighbouring tiles, so a grazing ray can show relief well beyond the mesh's
    // bounds (at 75 degrees S = 0.1 is 0.37 tiles away from the entry): the far plane is twice the farthest
    // bound. With a 32-bit float depth buffer this costs next to nothing in precision.
    const double margin = 0.01 * (farthest - std::min(nearest, farthest)) + 1e-6 * farthest;
    const double farPlane = 2.0 * farthest + margin;
    const double nearPlane = std::max(nearest - margin, farPlane * 1e-4);
    return {nearPlane, farPlane};
}

// The order the shader sees a live material's layers in: the layer that can move Eq. 2's sum most first
// (largest w_d,i (max d_i - min d_i)), so that the searches' first read most often settles whether a point
// is above the relief (relief_search.glsl, reliefBelow). The sums do not depend on the order, and the shader
// indexes its sampler array with constants only (a dynamic index is much slower on llvmpipe).
std::vector<std::size_t> shaderLayerOrder(const std::vector<GpuLayer>& layers) {
    std::vector<std::size_t> order(layers.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    const auto range = [&](std::size_t i) {
        return layers[i].weightDepth * (layers[i].depthMax - layers[i].depthMin);
    };
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return range(a) > range(b); });
    return order;
}

}  // namespace

// The live meta-relief's uniforms (relief_search.glsl, relief.frag.glsl metaShade), per layer in
// shaderLayerOrder: weights normalised as Eq. 1 and 2 do, each layer's AO rescale S_i now / S_i baked,
// S_i = S (w_d,i / W) t_i, and the bounds on what the later layers add to Eq. 2 (with 1e-6 of slack for the
// float rounding of the shader's sums).
void ReliefRenderer::Impl::setLiveUniforms(shared::ReliefUniforms& uniforms, const GpuMaterial& material,
                                           double depthScale, const ReliefSettings& relief) {
    const std::vector<GpuLayer>& layers = material.layers();
    const std::vector<std::size_t> order = shaderLayerOrder(layers);
    double sumDepth = 0.0, sumNormal = 0.0;
    for (const GpuLayer& layer : layers) {
        sumDepth += layer.weightDepth;
        sumNormal += layer.weightNormal;
    }
    double low = 0.0, high = 0.0;
    for (std::size_t i = layers.size(); i-- > 0;) {
        uniforms.uLayerRestLow[i].x = static_cast<float>(low - 1e-6);
        uniforms.uLayerRestHigh[i].x = static_cast<float>(high + 1e-6);
        const GpuLayer& layer = layers[order[i]];
        low += layer.weightDepth / sumDepth * layer.depthMin;
        high += layer.weightDepth / sumDepth * layer.depthMax;
    }
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const GpuLayer& layer = layers[order[i]];
        uniforms.uLayerTiling[i].x = static_cast<float>(layer.tiling);
        uniforms.uLayerNormalScale[i].x = static_cast<float>(layer.normalScale);
        uniforms.uLayerDepthWeight[i].x = static_cast<float>(layer.weightDepth / sumDepth);
        uniforms.uLayerNormalWeight[i].x =
            sumNormal > 0.0 ? static_cast<float>(layer.weightNormal / sumNormal) : 0.0f;
        const double now = depthScale * (layer.weightDepth / sumDepth) * layer.tiling;
        uniforms.uLayerAoScale[i].x = layer.aoDepthScale > 0.0 && relief.aoRescale != AoRescale::Off
                                          ? static_cast<float>(now / layer.aoDepthScale)
                                          : 1.0f;
    }
    uniforms.uLayerCount = static_cast<int>(layers.size());
    uniforms.uMetaConsistent = material.normalMode() == NormalMode::Consistent ? 1 : 0;
    int aoMode = 0;
    if (material.liveAo() == MetaAoMode::Multiply) aoMode = 1;
    if (material.liveAo() == MetaAoMode::Min) aoMode = 2;
    if (material.liveAo() == MetaAoMode::Exact && material.composedAoTexture() != 0) aoMode = 3;
    uniforms.uMetaAo = aoMode;
}

void ReliefRenderer::Impl::drawScene(const RenderRequest& request, int width, int height, bool encodeSrgb,
                                     const glm::vec4& clearColor) {
    const auto [nearPlane, farPlane] = clipPlanes(request);
    const glm::dmat4 viewProjection =
        projectionMatrix(request.camera, static_cast<double>(width) / height, nearPlane, farPlane) *
        viewMatrix(request.camera);
    const glm::mat4 viewProjectionF = toFloat(viewProjection);

    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_FRAMEBUFFER_SRGB);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    // Relief mapping is defined for the front side of a surface (the view ray must go into it).
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glClearColor(clearColor.r, clearColor.g, clearColor.b, clearColor.a);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    const ReliefSettings& relief = request.relief;
    const Lighting& lighting = request.lighting;
    for (std::size_t i = 0; i < request.objects.size(); ++i) {
        const SceneObject& object = request.objects[i];
        const GpuMaterial* material = object.material;
        ProgramVariant variant;
        variant.technique = relief.technique;
        variant.output = request.picture.output;
        variant.plain = material == nullptr;
        variant.shadows = relief.selfShadow;
        variant.depthCorrection = relief.depthCorrection;
        if (material != nullptr && relief.ao && material->hasAo()) {
            variant.ao = relief.aoRescale == AoRescale::Paper ? AoMode::Paper : AoMode::Baked;
        }
        variant.live = material != nullptr && material->isLive();
        const GLuint id = program(variant).id();

        const double depthScale =
            material != nullptr ? relief.depthScale.value_or(material->depthScale()) : 0.0;
        const glm::dmat3 linear(object.model);
        const double determinant = glm::determinant(linear);
        const glm::mat3 normalMatrix(glm::transpose(glm::inverse(linear)));
        // Zero-initialised: the members a variant does not read (the live arrays past the layer count,
        // the maxmip and cone values of the other techniques) hold 0.
        shared::ReliefUniforms uniforms{};
        uniforms.uModel = toFloat(object.model);
        uniforms.uNormalMatrix =
            glm::mat3x4(glm::vec4(normalMatrix[0], 0.0f), glm::vec4(normalMatrix[1], 0.0f),
                        glm::vec4(normalMatrix[2], 0.0f));
        uniforms.uMirror = determinant < 0.0 ? -1.0f : 1.0f;
        uniforms.uViewProjection = viewProjectionF;
        uniforms.uTiling = static_cast<float>(relief.tiling);
        uniforms.uEye = glm::vec3(request.camera.eye);
        uniforms.uDepthScale = static_cast<float>(depthScale);
        uniforms.uNormalScale =
            material != nullptr ? static_cast<float>(depthScale / material->depthScale()) : 1.0f;
        uniforms.uLinearSteps = relief.linearSteps;
        uniforms.uBinarySteps = relief.binarySteps;
        uniforms.uLightPosition = glm::vec3(lighting.lightPosition);
        uniforms.uLightColor = glm::vec3(lighting.lightColor);
        uniforms.uAmbient = static_cast<float>(lighting.ambient);
        uniforms.uSpecular = static_cast<float>(lighting.specular);
        uniforms.uShininess = static_cast<float>(lighting.shininess);
        uniforms.uAoScale =
            material != nullptr ? static_cast<float>(depthScale / material->aoDepthScale()) : 1.0f;
        uniforms.uPlainColor = glm::vec3(static_cast<float>(srgbToLinear(object.color.r)),
                                         static_cast<float>(srgbToLinear(object.color.g)),
                                         static_cast<float>(srgbToLinear(object.color.b)));
        uniforms.uEncodeSrgb = encodeSrgb ? 1 : 0;
        uniforms.uColorTiling = 1.0f;

        const GLuint sampler =
            request.picture.output == RenderOutput::Shaded ? searchSampler : baseLevelSampler;
        glUseProgram(id);
        if (variant.live) {
            setLiveUniforms(uniforms, *material, depthScale, relief);
            glBindTextureUnit(shared::kReliefUnit, flatRelief);
            glBindTextureUnit(shared::kReliefShadeUnit, flatRelief);
            const std::vector<GpuLayer>& layers = material->layers();
            const int colorLayer = material->colorLayer();
            glBindTextureUnit(shared::kColorUnit,
                              colorLayer >= 0 ? layers[static_cast<std::size_t>(colorLayer)].color : white);
            if (colorLayer >= 0)
                uniforms.uColorTiling =
                    static_cast<float>(layers[static_cast<std::size_t>(colorLayer)].tiling);
            // Searches and shading read the layers through one sampler (trilinear, or the base level for the
            // debug outputs): a second set of units with anisotropic filtering would need 16 more.
            const std::vector<std::size_t> order = shaderLayerOrder(layers);
            for (int layer = 0; layer < shared::kMaxLiveLayers; ++layer) {
                const bool used = layer < static_cast<int>(layers.size());
                const auto unit = static_cast<GLuint>(shared::kLayerUnit0 + layer);
                glBindTextureUnit(unit,
                                  used ? layers[order[static_cast<std::size_t>(layer)]].texture : flatRelief);
                glBindSampler(unit, sampler);
            }
            glBindTextureUnit(shared::kComposedAoUnit, material->composedAoTexture() != 0
                                                           ? material->composedAoTexture()
                                                           : flatRelief);
        } else {
            glBindTextureUnit(shared::kReliefUnit,
                              material != nullptr ? material->reliefTexture() : flatRelief);
            glBindTextureUnit(shared::kColorUnit, material != nullptr ? material->colorTexture() : white);
            glBindTextureUnit(shared::kReliefShadeUnit,
                              material != nullptr ? material->reliefTexture() : flatRelief);
        }
        if (material != nullptr && relief.technique == Technique::MaxMip) {
            glBindTextureUnit(shared::kMaxMipUnit, material->maxMipTexture());
            uniforms.uMaxMipLevels = material->maxMipLevels();
        }
        if (material != nullptr && relief.technique == Technique::Cone) {
            // coneTexture() first: it makes the cone map, and with it the ratio, on first use.
            glBindTextureUnit(shared::kConeMapUnit, material->coneTexture());
            uniforms.uConeMaxRatio = static_cast<float>(material->coneMaxRatio());
        }
        glBindSampler(shared::kReliefUnit, sampler);
        glNamedBufferSubData(uniformBuffer, 0, sizeof(uniforms), &uniforms);
        glBindBufferBase(GL_UNIFORM_BUFFER, shared::kReliefUniformsBinding, uniformBuffer);
        // A mirroring model turns counter-clockwise triangles clockwise on screen.
        glFrontFace(determinant < 0.0 ? GL_CW : GL_CCW);
        glBindVertexArray(object.mesh->vertexArray());
        glDrawElements(GL_TRIANGLES, object.mesh->indexCount(), GL_UNSIGNED_INT, nullptr);
        checkGl(("ReliefRenderer: drawing object " + std::to_string(i) + " (" +
                 variantName(canonical(variant)) + ")")
                    .c_str());
    }
    glBindVertexArray(0);
    glBindSampler(shared::kReliefUnit, 0);
    for (int layer = 0; layer < shared::kMaxLiveLayers; ++layer)
        glBindSampler(static_cast<GLuint>(shared::kLayerUnit0 + layer), 0);
    glBindBufferBase(GL_UNIFORM_BUFFER, shared::kReliefUniformsBinding, 0);
    glUseProgram(0);
    glFrontFace(GL_CCW);
}

ReliefRenderer::ReliefRenderer() : mImpl(std::make_unique<Impl>()) {}

ReliefRenderer::~ReliefRenderer() = default;

void ReliefRenderer::prepare(const ProgramVariant& variant) {
    mImpl->program(variant);
}

namespace {

// k of the k x k supersampling grid for `samples` per pixel, limited so that the supersampled picture fits
// the driver's renderbuffer size.
int supersamplingFactor(const PictureSettings& picture) {
    int factor = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(picture.samples)))));
    GLint maxSize = 4096;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    while (factor > 1 && std::max(picture.width, picture.height) * factor > maxSize) --factor;
    return factor;
}

}  // namespace

Image ReliefRenderer::render(const RenderRequest& request) {
    validateRequest(request);
    const PictureSettings& picture = request.picture;
    const bool shaded = picture.output == RenderOutput::Shaded;
    // Shaded: supersampled on a k x k grid per pixel (k = round(sqrt(samples))), in linear half-float colour,
    // box-filtered in linear and encoded to sRGB here. Supersampling rather than MSAA, because MSAA shades
    // once per pixel: it smooths the polygons' edges but not what relief mapping draws inside them (the
    // relief's own silhouettes, shadow edges, fine texture).
    // Debug outputs: 32-bit float (uv needs 16 bits of precision), one sample (CONVENTIONS §7).
    const int factor = shaded ? supersamplingFactor(picture) : 1;
    const int outWidth = picture.width;
    const int outHeight = picture.height;
    const int width = outWidth * factor;
    const int height = outHeight * factor;
    BindingGuard guard;
    mImpl->target.ensure(width, height, shaded ? GL_RGBA16F : GL_RGBA32F, "ReliefRenderer");
    const RenderTarget& target = mImpl->target;

    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer());
    const glm::vec4 clear = shaded ? glm::vec4(static_cast<float>(srgbToLinear(picture.background.r)),
                                               static_cast<float>(srgbToLinear(picture.background.g)),
                                               static_cast<float>(srgbToLinear(picture.background.b)), 1.0f)
                                   : glm::vec4(0.0f);
    mImpl->drawScene(request, width, height, false, clear);

    std::vector<float> pixels(static_cast<std::size_t>(width) * height * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.framebuffer());
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, pixels.data());
    checkGl("ReliefRenderer::render: read-back");

    const int channels = shaded || picture.output == RenderOutput::Uv ? 3 : 1;
    const float weight = 1.0f / static_cast<float>(factor * factor);
    Image image = Image::uninitialized(outWidth, outHeight, channels);
    for (int y = 0; y < outHeight; ++y) {
        float* row = image.row(y);
        for (int x = 0; x < outWidth; ++x) {
            for (int c = 0; c < channels; ++c) {
                float sum = 0.0f;
                for (int j = 0; j < factor; ++j) {
                    // GL's row 0 is the bottom one; the picture's row 0 is the top (CONVENTIONS §7).
                    const float* source =
                        pixels.data() + static_cast<std::size_t>(height - 1 - (y * factor + j)) * width * 4;
                    for (int i = 0; i < factor; ++i) sum += source[(x * factor + i) * 4 + c];
                }
                row[x * channels + c] = shaded ? static_cast<float>(linearToSrgb(sum * weight)) : sum;
            }
        }
    }
    return image;
}

void ReliefRenderer::draw(const RenderRequest& request, int viewportWidth, int viewportHeight) {
    if (viewportWidth < 1 || viewportHeight < 1) {
        throw Error(ErrorKind::InvalidInput, "ReliefRenderer::draw: viewport " +
                                                 std::to_string(viewportWidth) + "x" +
                                                 std::to_string(viewportHeight) + " is empty");
    }
    RenderRequest shadedRequest = request;
    shadedRequest.picture.output = RenderOutput::Shaded;
    shadedRequest.picture.width = viewportWidth;
    shadedRequest.picture.height = viewportHeight;
    validateRequest(shadedRequest);
    const glm::dvec3& background = request.picture.background;
    // Values are written sRGB-encoded by the shader, so the clear colour is the encoded background as is.
    mImpl->drawScene(shadedRequest, viewportWidth, viewportHeight, true,
                     glm::vec4(glm::vec3(background), 1.0f));
}

}  // namespace strata::gl
