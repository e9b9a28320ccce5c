// A GDM render's picture (Scene::gdm): what `strata render --gdm` writes and strata-view shows, drawn by a
// GdmRenderer that holds the scene's GDM, mesh and volumes. The picture follows PictureSettings as a relief
// render's does (render_settings.h): shaded is sRGB colour supersampled on a k x k grid (k = round(sqrt(
// samples)), box-filtered in linear colour) over the background; uvw, shadow and mask are CONVENTIONS §8's
// values, one sample per pixel.
#pragma once

#include "strata/gdm/prism_shell.h"
#include "strata/gdm/scene_gdm.h"
#include "strata/gl/gdm_renderer.h"
#include "strata/image/image.h"
#include "strata/scene/camera.h"
#include "strata/scene/render_settings.h"
#include "strata/scene/scene.h"

namespace strata::gl {

// Gives `renderer` what a scene draws: the GDM that `gdm` reads (raw or its SVD), its volumes (occupancy,
// albedo, and the signed distance when the asset has one), `mesh`'s prism shell at the scene's tiling and
// shell thickness (height: the GDM's H), the scene's light frame and lighting, and with an environment
// (gdm.rtv and gdm.environment) the RTV, the mesh's macro transfer (bakeMacroTransfer from the top of the
// shell) and the environment. Returns the shell's options.
// Throws as the GdmRenderer setters.
PrismShellOptions prepareGdmRenderer(GdmRenderer& renderer, const SceneGdm& gdm, const Mesh& mesh,
                                     const Scene& scene);

// Throws Error(InvalidInput) for an output that is not a GDM one (kGdmOutputs), and as GdmRenderer's render
// and renderShaded (the volumes must be set for shaded and for refine and march).
// Layout: shaded 3 channels sRGB; uvw 4 channels; shadow and mask 1 channel.
Image renderGdmPicture(GdmRenderer& renderer, const Camera& camera, const Lighting& lighting,
                       const PictureSettings& picture, GdmTechnique technique);

}  // namespace strata::gl
