// Comparison metrics and diff pictures for the verification scene (include/strata/trace/render_compare.h).
#include "strata/trace/render_compare.h"

#include "strata/core/error.h"
#include "strata/image/image_io.h"

#include <algorithm>
#include <cmath>
#include <system_error>
#include <utility>

namespace strata {

namespace {

std::string sizeOf(const Image& image) {
    return std::to_string(image.width()) + " x " + std::to_string(image.height()) + " x " +
           std::to_string(image.channels());
}

void requireShape(const Image& image, const char* what, int channels) {
    if (image.empty() || image.channels() != channels) {
        throw Error(ErrorKind::InvalidInput, std::string("render comparison: ") + what +
                                                 " must be a non-empty " + std::to_string(channels) +
                                                 "-channel image, got " + sizeOf(image));
    }
}

void requireSameSize(const Image& a, const char* aWhat, const Image& b, const char* bWhat) {
    if (a.width() != b.width() || a.height() != b.height()) {
        throw Error(ErrorKind::InvalidInput, std::string("render comparison: ") + aWhat + " (" + sizeOf(a) +
                                                 ") and " + bWhat + " (" + sizeOf(b) + ") differ in size");
    }
}

void requireTextureSize(int textureWidth, int textureHeight) {
    if (textureWidth < 1 || textureHeight < 1) {
        throw Error(ErrorKind::InvalidInput,
                    "render comparison: texture size must be >= 1 texel per side, got " +
                        std::to_string(textureWidth) + " x " + std::to_string(textureHeight));
    }
}

void requireUvPair(const Image& reference, const Image& test) {
    requireShape(reference, "the reference uv image", 3);
    requireShape(test, "the test uv image", 3);
    requireSameSize(reference, "the reference uv image", test, "the test uv image");
}

bool hits(const Image& uv, int x, int y) {
    return uv.at(x, y, 2) > 0.5f;
}

// a - b modulo 1, in [-1/2, 1/2].
double wrappedDifference(double a, double b) {
    const double d = a - b;
    return d - std::round(d);
}

// Toroidal uv distance of pixel (x, y) in texels (both images hit there).
double uvErrorTexels(const Image& reference, const Image& test, int x, int y, int textureWidth,
                     int textureHeight) {
    const double du = wrappedDifference(reference.at(x, y, 0), test.at(x, y, 0)) * textureWidth;
    const double dv = wrappedDifference(reference.at(x, y, 1), test.at(x, y, 1)) * textureHeight;
    return std::sqrt(du * du + dv * dv);
}

// Nearest-rank percentile of n >= 1 values: the ceil(p n / 100)-th smallest (from 1). Reorders `values`.
double percentile(std::vector<double>& values, double p) {
    const auto n = static_cast<long>(values.size());
    const long rank = std::clamp(static_cast<long>(std::ceil(p / 100.0 * static_cast<double>(n))), 1L, n);
    const auto nth = values.begin() + (rank - 1);
    std::nth_element(values.begin(), nth, values.end());
    return *nth;
}

}  // namespace

UvComparison compareUv(const Image& reference, const Image& test, int textureWidth, int textureHeight) {
    requireUvPair(reference, test);
    requireTextureSize(textureWidth, textureHeight);

    UvComparison result;
    std::vector<double> errors;
    for (int y = 0; y < reference.height(); ++y) {
        for (int x = 0; x < reference.width(); ++x) {
            const bool referenceHit = hits(reference, x, y);
            const bool testHit = hits(test, x, y);
            result.referenceHits += referenceHit;
            result.testHits += testHit;
            if (referenceHit != testHit) ++result.hitMismatch;
            if (referenceHit && testHit)
                errors.push_back(uvErrorTexels(reference, test, x, y, textureWidth, textureHeight));
        }
    }
    result.mismatchFraction =
        static_cast<double>(result.hitMismatch) / static_cast<double>(std::max(result.referenceHits, 1L));
    result.bothHit = static_cast<long>(errors.size());
    if (!errors.empty()) {
        result.max = *std::max_element(errors.begin(), errors.end());
        result.p99 = percentile(errors, 99.0);
        result.p50 = percentile(errors, 50.0);
    }
    return result;
}

MaskAgreement compareShadow(const Image& referenceShadow, const Image& testShadow, const Image& referenceUv,
                            const Image& testUv) {
    requireUvPair(referenceUv, testUv);
    requireShape(referenceShadow, "the reference shadow image", 1);
    requireShape(testShadow, "the test shadow image", 1);
    requireSameSize(referenceShadow, "the reference shadow image", referenceUv, "the reference uv image");
    requireSameSize(testShadow, "the test shadow image", referenceUv, "the reference uv image");

    MaskAgreement result;
    for (int y = 0; y < referenceUv.height(); ++y) {
        for (int x = 0; x < referenceUv.width(); ++x) {
            if (!hits(referenceUv, x, y) || !hits(testUv, x, y)) continue;
            ++result.compared;
            if ((referenceShadow.at(x, y) > 0.5f) == (testShadow.at(x, y) > 0.5f)) ++result.agree;
        }
    }
    if (result.compared > 0)
        result.fraction = static_cast<double>(result.agree) / static_cast<double>(result.compared);
    return result;
}

Image uvDiffImage(const Image& reference, const Image& test, int textureWidth, int textureHeight,
                  double saturateTexels) {
    requireUvPair(reference, test);
    requireTextureSize(textureWidth, textureHeight);
    if (!(std::isfinite(saturateTexels) && saturateTexels > 0.0)) {
        throw Error(
            ErrorKind::InvalidInput,
            "render comparison: saturateTexels must be finite and > 0, got " + formatNumber(saturateTexels));
    }

    Image diff(reference.width(), reference.height(), 3);
    for (int y = 0; y < reference.height(); ++y) {
        for (int x = 0; x < reference.width(); ++x) {
            const bool referenceHit = hits(reference, x, y);
            const bool testHit = hits(test, x, y);
            if (referenceHit && testHit) {
                const double error = uvErrorTexels(reference, test, x, y, textureWidth, textureHeight);
                diff.at(x, y, 1) = static_cast<float>(std::min(error / saturateTexels, 1.0));
            } else if (referenceHit) {
                diff.at(x, y, 0) = 1.0f;
            } else if (testHit) {
                diff.at(x, y, 2) = 1.0f;
            }
        }
    }
    return diff;
}

std::vector<std::filesystem::path> writeComparisonImages(const std::filesystem::path& directory,
                                                         const std::string& stem, const Image& expected,
                                                         const Image& actual, const Image& diff) {
    if (stem.empty() || stem.find('/') != std::string::npos) {
        throw Error(
            ErrorKind::InvalidInput,
            "comparison images: the file stem must be non-empty and contain no '/', got \"" + stem + "\"");
    }
    const std::pair<const char*, const Image*> outputs[] = {
        {"expected", &expected}, {"actual", &actual}, {"diff", &diff}};
    for (const auto& [name, image] : outputs) {
        if (image->empty()) {
            throw Error(ErrorKind::InvalidInput, std::string("comparison images: the ") + name +
                                                     " image for \"" + stem + "\" is empty");
        }
    }
    std::error_code error;
    std::filesystem::create_directories(directory, error);
    if (error) {
        throw Error(ErrorKind::Io,
                    directory.string() + ": cannot create the directory (" + error.message() + ")");
    }

    std::vector<std::filesystem::path> paths;
    for (const auto& [name, image] : outputs) {
        paths.push_back(directory / (stem + "_" + name + ".png"));
        writePng(paths.back(), *image, PngWriteOptions{PngBitDepth::Sixteen, false});
    }
    return paths;
}

}  // namespace strata
