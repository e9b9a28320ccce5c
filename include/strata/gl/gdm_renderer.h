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

#include "strata/gdm/gdm.h"
#include "strata/gdm/gdm_svd.h"
#include "strata/gdm/gdm_trace.h"
#include "strata/scene/camera.h"

#include <glm/vec3.hpp>

namespace strata::gl {

GdmSceneImages renderGdmScene(const Gdm& gdm, const Camera& camera, glm::dvec3 light, int width, int height,
                              GdmDirectionLookup directions = GdmDirectionLookup::Nearest);
GdmSceneImages renderGdmScene(const GdmSvd& svd, const Camera& camera, glm::dvec3 light, int width,
                              int height, GdmDirectionLookup directions = GdmDirectionLookup::Nearest);

}  // namespace strata::gl
