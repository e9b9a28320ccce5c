// strata::gl::ReliefRenderer: relief mapping on arbitrary polygonal surfaces in OpenGL 4.5 core
// (Policarpo, Oliveira, Comba 2005, "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces", Sec. 3 and
// the appendix's Cg shader), with the meta-relief paper's texture-space AO (Limberger et al. 2015, Sec. IV).
// docs/renderer.md describes the techniques, shader variants, texture-to-world scale and measured accuracy.
// It draws meshes uploaded with uploadMesh (gpu_mesh.h) and materials uploaded with uploadMaterial,
// uploadLiveMaterial or uploadDualDepth (gpu_material.h).
//
// Everything here needs a current OpenGL 4.5 core context (HeadlessContext, or the viewer's window), and
// GPU objects must be destroyed while the context that made them is current. Pictures come back with
// row 0 = top (CONVENTIONS §7).
#pragma once

#include "strata/image/image.h"
#include "strata/scene/camera.h"
#include "strata/scene/render_settings.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <memory>
#include <vector>

namespace strata::gl {

class GpuMesh;
class GpuMaterial;
// One program of the renderer's shaders (the technique, output and flags it is built for). Internal to the
// renderer (src/gl/relief_program.h): only prepare() names it, for the tests that compile every variant.
struct ProgramVariant;

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
