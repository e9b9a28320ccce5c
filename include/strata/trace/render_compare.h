// Metrics that judge a renderer's debug outputs (the GL renderer's) against the exact reference of the
// verification scene (quad_reference.h, CONVENTIONS §7), and the diff pictures that failing tests write.
//
// A uv image here is the float form of §7's uv output: 3 channels, (u, v, hit) with u, v in [0, 1] and
// hit > 0.5 where the pixel's ray hits the relief (channel 2 is 1 or 0 in the reference; a GL read-back of
// the 16-bit encoding divides by 65535). Texture coordinates wrap (CONVENTIONS §1), so the uv error of a
// pixel is the toroidal one: per axis the difference taken modulo 1 into [-1/2, 1/2], then scaled to
// texels of the depth map and combined as a Euclidean length:
//     error = sqrt((W du)^2 + (H dv)^2)   (W x H = the depth map's size in texels)
// so u = 0.999 against u = 0.001 is 0.002 tiles apart, not 0.998.
//
// Failure contract: images of the wrong shape (sizes that differ, a uv image without 3 channels, a mask
// without 1 channel, an empty image) and non-positive sizes or limits throw Error(InvalidInput) naming the
// argument and its value; they come from a renderer or a file, not from this code.
#pragma once

#include "strata/image/image.h"

#include <filesystem>
#include <string>
#include <vector>

namespace strata {

struct UvComparison {
    long referenceHits = 0;       // pixels the reference hits
    long testHits = 0;            // pixels the test image hits
    long hitMismatch = 0;         // pixels where exactly one of the two hits
    double mismatchFraction = 0;  // hitMismatch / max(referenceHits, 1)
    long bothHit = 0;             // pixels where both hit
    // uv error in texels over the bothHit pixels (see the header comment); 0 when bothHit == 0. Percentiles
    // are nearest-rank: the smallest error e such that at least p % of the bothHit pixels have error <= e
    // (sorted error number ceil(p n / 100), counting from 1).
    double p50 = 0, p99 = 0, max = 0;
};

// reference, test: 3-channel uv images of one size (channel 2 = hit flag, > 0.5 = hit). textureWidth,
// textureHeight: the depth map's size in texels, >= 1.
UvComparison compareUv(const Image& reference, const Image& test, int textureWidth, int textureHeight);

struct MaskAgreement {
    long compared = 0;    // pixels compared
    long agree = 0;       // of those, pixels where the two masks agree
    double fraction = 1;  // agree / compared; 1 when nothing was compared
};

// Over the pixels where both uv images hit: does the 1-channel shadow mask (> 0.5 = lit) agree? All four
// images have one size; the shadows have 1 channel, the uv images 3.
MaskAgreement compareShadow(const Image& referenceShadow, const Image& testShadow, const Image& referenceUv,
                            const Image& testUv);

// A diff picture for failing tests, RGB, same size as the inputs (3-channel uv images of one size):
//   black  where neither hits, or both hit with zero uv error;
//   red    (1, 0, 0) where only the reference hits;
//   blue   (0, 0, 1) where only the test hits;
//   green  (0, g, 0) where both hit, g = min(error / saturateTexels, 1) with the uv error in texels.
// saturateTexels: > 0 (default 4 texels).
Image uvDiffImage(const Image& reference, const Image& test, int textureWidth, int textureHeight,
                  double saturateTexels = 4.0);

// Writes expected, actual and diff as 16-bit PNGs (values clamped to [0, 1], writePng) into `directory`,
// creating it if needed, named <stem>_expected.png, <stem>_actual.png, <stem>_diff.png; for tests to call on
// failure. Returns the three paths in that order. The images may have any size and 1 to 4 channels each.
// Throws Error(InvalidInput) for an empty stem, a stem containing '/', or an empty image; Error(Io) when the
// directory cannot be created or a file cannot be written.
std::vector<std::filesystem::path> writeComparisonImages(const std::filesystem::path& directory,
                                                         const std::string& stem, const Image& expected,
                                                         const Image& actual, const Image& diff);

}  // namespace strata
