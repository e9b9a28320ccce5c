// Environments: distant radiance around a scene, as equirectangular maps (CONVENTIONS §9) and as the
// built-in procedural skies, and their projection onto band-3 spherical harmonics (spherical_harmonics.h).
//
// Equirectangular maps (CONVENTIONS §9, exactly): world space, +z up, linear RGB radiance. A W x H map's
// row j covers polar angles [j pi / H, (j + 1) pi / H] (row 0 touches the zenith +z, row H - 1 the nadir) and
// its texel centre is at polar angle (j + 0.5) pi / H; column i covers azimuths [i 2 pi / W, (i + 1) 2 pi /
// W] from +x towards +y, centre at (i + 0.5) 2 pi / W. The direction of polar t and azimuth p is (sin t cos
// p, sin t sin p, cos t).
//
// Projection of a map (projectEquirect): each texel is taken as constant over its cell, valued at its centre
// direction, and weighted by the cell's exact solid angle 2 pi / W (cos t0 - cos t1), t0 and t1 the row's
// polar bounds. The weights add up to 4 pi exactly. The error against the integral of the underlying
// continuous radiance is that of a midpoint rule in the polar angle and in azimuth: O((pi / H)^2) for
// radiance that is smooth within each cell (docs/environment.md gives measured numbers).
//
// Units: radiance in whatever unit the map holds (the skies are in relative units: the overcast sky's zenith
// is 1). Errors: see readEnvironmentMap, makeEnvironment, openEnvironment.
#pragma once

#include "strata/environment/spherical_harmonics.h"
#include "strata/image/image.h"

#include <glm/vec3.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace strata {

// The unit direction of polar angle `polar` (radians from +z) and azimuth `azimuth` (radians from +x towards
// +y).
glm::dvec3 sphericalDirection(double polar, double azimuth);

// The centre direction of texel (column, row) of a width x height equirectangular map (§9).
glm::dvec3 equirectTexelDirection(int column, int row, int width, int height);

// The exact solid angle (steradians) of one texel of row `row` of a width x height map:
// 2 pi / width * (cos(row pi / height) - cos((row + 1) pi / height)).
double equirectTexelSolidAngle(int row, int width, int height);

// A texel of an equirectangular map.
struct EquirectTexel {
    int column = 0;  // [0, width)
    int row = 0;     // [0, height)
};

// The texel whose cell holds `direction` (normalised here; checked non-zero and finite). A direction on a
// cell boundary goes to the cell after it (larger index), clamped to the map; the poles belong to rows 0
// and H - 1.
EquirectTexel equirectTexelOf(const glm::dvec3& direction, int width, int height);

// Projection of an equirectangular map onto SH, as described above. `equirect`: 1 channel (grey, used for
// all of R, G, B), 3 (RGB) or 4 (RGBA, alpha ignored) channels, any size (2:1 is usual); checked non-empty.
ShColor projectEquirect(const Image& equirect);

// Reads an equirectangular environment map. It must be OpenEXR (linear radiance, §9): any other image
// format throws Error(InvalidInput) naming the file and the format found. Grey (Y, YA) files become RGB;
// RGBA drops alpha. A NaN, infinite or negative value throws Error(InvalidInput) naming the file, the texel
// (column, row), the channel and the value. Unreadable, corrupt or unsupported files throw as readImage does
// (Io / InvalidInput / Unsupported, the message starting with the path). Returns a 3-channel image.
Image readEnvironmentMap(const std::filesystem::path& path);

// A radiance function: linear RGB radiance arriving from unit `direction` (world space, +z up).
using RadianceFunction = std::function<glm::dvec3(const glm::dvec3& direction)>;

// An equirectangular rendering (3 channels) of `radiance`: texel (i, j) holds radiance(its centre
// direction), point-sampled (no filtering: a feature narrower than a texel can be missed or widened).
// width and height in [1, Image::kMaxDimension] (checked).
Image renderEquirect(const RadianceFunction& radiance, int width, int height);

// An environment: a name, its radiance in every direction, an equirectangular map of it and its SH.
class Environment {
public:
    // A procedural environment; its map is renderEquirect(radiance, width, height).
    Environment(std::string name, RadianceFunction radiance, int width, int height);
    // An environment given by a map (3 channels, as readEnvironmentMap returns): radiance(d) is the value of
    // the texel whose cell holds d (nearest texel, no interpolation).
    Environment(std::string name, Image equirect);

    const std::string& name() const { return mName; }
    glm::dvec3 radiance(const glm::dvec3& direction) const;
    // The equirectangular map (3 channels, linear RGB).
    const Image& map() const { return mMap; }
    // projectEquirect(map()), computed at construction.
    const ShColor& sh() const { return mSh; }
    bool isProcedural() const { return static_cast<bool>(mRadiance); }

private:
    std::string mName;
    RadianceFunction mRadiance;  // empty for a map-backed environment
    Image mMap;
    ShColor mSh{};
};

// The built-in procedural skies, in this order (docs/environment.md shows each):
//   sky-clear     a blue gradient sky (zenith (0.20, 0.40, 0.85) to horizon (0.80, 0.88, 1.00)), a glow and a
//   sun
//                 disc of 2 degrees' angular radius (enlarged from the real 0.27 so that a 512 x 256 map
//                 resolves it) at 35 degrees elevation, azimuth 60 degrees, radiance 800 (1, 0.96, 0.9);
//                 ground below the horizon a constant (0.22, 0.20, 0.17).
//   sky-overcast  the CIE standard overcast sky, L(t) = (1 + 2 cos t) / 3 (zenith 1, horizon 1/3), grey;
//   ground
//                 a Lambertian of albedo 0.2 under it: 0.2 * 7 / 9 (the sky's horizontal irradiance is 7 pi /
//                 9).
//   sky-sunset    a warm horizon towards a low sun (3 degrees elevation, azimuth 250 degrees, 1.5 degrees
//                 radius), a dark blue zenith, dark ground.
//   studio        a dark grey room with three round soft boxes: a key light (elevation 40, azimuth -45,
//                 radius 12 degrees, radiance 6), a fill (15, 150, 18 degrees, 1.2) and a top-back rim light
//                 (70, 200, 8 degrees, 3).
// All are finite and non-negative everywhere, and continuous except at the horizon and the discs' edges.
std::vector<std::string> environmentList();

// The radiance function of a built-in sky. An unknown name throws Error(InvalidInput) naming it and listing
// environmentList().
RadianceFunction skyRadiance(const std::string& name);

// A built-in sky as an Environment with a width x height map (default 512 x 256). Unknown name: as
// skyRadiance. width or height outside [1, Image::kMaxDimension]: Error(InvalidInput) naming the value.
Environment makeEnvironment(const std::string& name, int width = 512, int height = 256);

// An environment read from an equirectangular EXR (readEnvironmentMap's errors); its name is the path.
Environment loadEnvironment(const std::filesystem::path& path);

// What a --env flag takes: a built-in sky's name (makeEnvironment at width x height), or else a path to an
// EXR (loadEnvironment; width and height unused). A string that is neither an existing file nor a built-in
// name throws Error(InvalidInput) naming it and listing the built-in names.
Environment openEnvironment(const std::string& nameOrPath, int width = 512, int height = 256);

}  // namespace strata
