// A picture of a mesostructure, for `strata meso` and docs/gdm.md, made on the CPU by sphere tracing its
// distance bound (mesostructure.h): tiles x tiles tiles (the periodic solid cut by the box [0, tiles]^2 x
// [0, H], as the verification scene of CONVENTIONS §8 cuts it) over a grey floor at z = 0 with the tile
// borders drawn, seen from above at an angle through an orthographic camera, lit by one directional light
// with hard shadows (traced through the infinite periodic solid) and a little ambient light dimmed by a
// five-sample ambient-occlusion estimate. Albedo from the mesostructure, shading in linear light, written
// sRGB-encoded. Not a reference: the verification renders of the GDM do that.
#pragma once

#include "strata/gdm/mesostructure.h"
#include "strata/gdm/solid_mesh.h"
#include "strata/image/image.h"

#include <filesystem>
#include <vector>

namespace strata {

struct MesostructurePreviewParams {
    int size = 256;                  // width = height, pixels, [16, 4096]
    int tiles = 2;                   // tiles shown along u and along v, [1, 8]
    double elevationDegrees = 45.0;  // of the camera above the tile plane, (0, 90]
    double azimuthDegrees = -125.0;  // of the camera, from +u towards +v
};

// An sRGB-encoded RGB image, size x size, one sample per pixel. Throws Error(InvalidInput) for parameters
// out of range.
Image renderMesostructurePreview(const Mesostructure& meso, const MesostructurePreviewParams& params = {});

// Writes DIR/mesh.obj (writeSolidObj) and DIR/preview.png (8-bit RGB) all or nothing: both are written into a
// staging directory beside DIR and then moved in, so a failure leaves DIR as it was (or not created).
// Returns the paths written. Throws Error(Io) if they cannot be written.
std::vector<std::filesystem::path> writeMesostructureOutputs(const std::filesystem::path& dir,
                                                             const SolidMesh& mesh, const Image& preview);

}  // namespace strata
