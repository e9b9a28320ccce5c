#include "strata/relief/import.h"

#include "strata/core/error.h"
#include "strata/image/image_ops.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

namespace strata {

namespace {

// "0.98", "-0.05": correlations in the summary line.
std::string formatCorrelation(double r) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.2f", r);
    return buffer;
}

[[noreturn]] void invalid(const std::string& message) {
    throw Error(ErrorKind::InvalidInput, message);
}

void validate(const Image& photo, const PhotoImportParams& p) {
    if (photo.empty()) invalid("photo: the image is empty");
    auto checkWeight = [](double w, const char* field) {
        if (!std::isfinite(w) || w < 0.0)
            invalid(std::string(field) + ": must be a finite number >= 0, got " + formatNumber(w));
    };
    checkWeight(p.weightLarge, "weightLarge");
    checkWeight(p.weightMedium, "weightMedium");
    checkWeight(p.weightSmall, "weightSmall");
    if (p.weightLarge == 0.0 && p.weightMedium == 0.0 && p.weightSmall == 0.0)
        invalid("weightLarge, weightMedium, weightSmall: all are 0, at least one must be > 0");

    if (!std::isfinite(p.sigmaSmall) || p.sigmaSmall < 0.0)
        invalid("sigmaSmall: must be a finite number >= 0 (tile widths), got " + formatNumber(p.sigmaSmall));
    auto checkAbove = [](double sigma, const char* field, double below, const char* belowField) {
        if (!std::isfinite(sigma) || !(sigma > below))
            invalid(std::string(field) + ": must be > " + belowField + " (" + formatNumber(below) +
                    "), got " + formatNumber(sigma));
    };
    checkAbove(p.sigmaMedium, "sigmaMedium", p.sigmaSmall, "sigmaSmall");
    checkAbove(p.sigmaLarge, "sigmaLarge", p.sigmaMedium, "sigmaMedium");
    checkAbove(p.sigmaHuge, "sigmaHuge", p.sigmaLarge, "sigmaLarge");
    // Wider than a tile, a wrap-around Gaussian is flat to within exp(-2 pi^2) of the mean: nothing
    // would be dropped any more, so a larger value is a mistake (probably texels instead of tile widths).
    if (p.sigmaHuge > 1.0) invalid("sigmaHuge: must be <= 1 (tile widths), got " + formatNumber(p.sigmaHuge));

    if (!std::isfinite(p.depthScale) || p.depthScale <= 0.0)
        invalid("depthScale: must be a finite number > 0, got " + formatNumber(p.depthScale));
}

// An extended box filter (Gwosdek et al. 2011): weight 1 on [-radius, radius] and `alpha` in [0, 1)
// on +-(radius + 1), normalised. Its variance is (r(r+1)(2r+1)/3 + 2 alpha (r+1)^2) / (2r+1+2 alpha);
// choosing r and alpha as below makes it equal `variance` exactly, which a plain box of integer width
// cannot do.
struct ExtendedBox {
    int radius;
    double alpha;
};

ExtendedBox extendedBox(double variance) {
    // The largest r whose plain box variance r(r+1)/3 does not exceed the target ...
    const int r = static_cast<int>(std::floor((std::sqrt(1.0 + 12.0 * variance) - 1.0) * 0.5));
    const double rd = r;
    // ... and the end weight that adds the rest.
    const double alpha =
        (2.0 * rd + 1.0) * (rd * (rd + 1.0) / 3.0 - variance) / (2.0 * (variance - (rd + 1.0) * (rd + 1.0)));
    return {r, std::clamp(alpha, 0.0, 1.0)};
}

// One wrap-around extended box along rows (x), with a running sum: O(1) per texel whatever the radius.
// A radius wider than the image simply counts texels more than once, which is exactly what a
// convolution on the torus does.
Image boxAlongX(const Image& in, const ExtendedBox& box) {
    const int w = in.width();
    const int r = box.radius;
    const double norm = 1.0 / (2.0 * r + 1.0 + 2.0 * box.alpha);
    Image out(w, in.height(), 1);
    for (int y = 0; y < in.height(); ++y) {
        const float* src = in.row(y);
        float* dst = out.row(y);
        auto value = [&](int x) { return static_cast<double>(src[Image::wrap(x, w)]); };
        double sum = 0.0;
        for (int j = -r; j <= r; ++j) sum += value(j);
        for (int x = 0; x < w; ++x) {
            const double outerRight = value(x + r + 1);
            dst[x] = static_cast<float>((sum + box.alpha * (value(x - r - 1) + outerRight)) * norm);
            sum += outerRight - value(x - r);
        }
    }
    return out;
}

// The same along columns (y), keeping one running sum per column so that rows are read in order.
Image boxAlongY(const Image& in, const ExtendedBox& box) {
    const int w = in.width();
    const int h = in.height();
    const int r = box.radius;
    const double norm = 1.0 / (2.0 * r + 1.0 + 2.0 * box.alpha);
    Image out(w, h, 1);
    std::vector<double> sums(static_cast<std::size_t>(w), 0.0);
    for (int j = -r; j <= r; ++j) {
        const float* src = in.row(Image::wrap(j, h));
        for (int x = 0; x < w; ++x) sums[static_cast<std::size_t>(x)] += static_cast<double>(src[x]);
    }
    for (int y = 0; y < h; ++y) {
        const float* above = in.row(Image::wrap(y - r - 1, h));
        const float* below = in.row(Image::wrap(y + r + 1, h));
        const float* leaving = in.row(Image::wrap(y - r, h));
        float* dst = out.row(y);
        for (int x = 0; x < w; ++x) {
            double& sum = sums[static_cast<std::size_t>(x)];
            const auto entering = static_cast<double>(below[x]);
            dst[x] =
                static_cast<float>((sum + box.alpha * (static_cast<double>(above[x]) + entering)) * norm);
            sum += entering - static_cast<double>(leaving[x]);
        }
    }
    return out;
}

// Four passes: the kernel along each axis is then the Irwin-Hall (4) shape, within 3.5% of the
// Gaussian's peak value everywhere, and a blurred image with hard edges stays within about 1% of
// its value range of the exact Gaussian's result (docs/import-from-photo.md has the measurements).
// Three passes leave 6% and 1.5%; six still leave 2.5% and 0.8%, for 50% more time.
constexpr int kBoxPasses = 4;

// Wrap-around Gaussian blur of a 1-channel image with standard deviations in texels along x and y.
Image blurWrapped(const Image& image, double sigmaX, double sigmaY) {
    if (sigmaX == sigmaY && sigmaX <= kExactBlurSigmaTexels) return gaussianBlur(image, sigmaX);
    Image out = image;
    if (sigmaX > 0.0) {
        const ExtendedBox box = extendedBox(sigmaX * sigmaX / kBoxPasses);
        for (int pass = 0; pass < kBoxPasses; ++pass) out = boxAlongX(out, box);
    }
    if (sigmaY > 0.0) {
        const ExtendedBox box = extendedBox(sigmaY * sigmaY / kBoxPasses);
        for (int pass = 0; pass < kBoxPasses; ++pass) out = boxAlongY(out, box);
    }
    return out;
}

// G_sigma L with sigma in tile widths: the tile is the unit square of (u, v) whatever the image's
// aspect (CONVENTIONS §1), so sigma is W * sigma texels along x and H * sigma along y.
Image blurTile(const Image& luma, double sigma) {
    if (sigma <= 0.0) return luma;
    return blurWrapped(luma, sigma * luma.width(), sigma * luma.height());
}

Image photoColor(const Image& photo) {
    Image color(photo.width(), photo.height(), 3);
    const bool rgb = photo.channels() >= 3;
    for (int y = 0; y < photo.height(); ++y)
        for (int x = 0; x < photo.width(); ++x)
            for (int c = 0; c < 3; ++c) color.at(x, y, c) = photo.at(x, y, rgb ? c : 0);
    return color;
}

struct Correlation {
    double r;      // Pearson r; 0 where undefined
    bool defined;  // false where either side has no variance
};

// Pearson correlation of channel c of a and b (same size), in double precision.
Correlation pearson(const Image& a, const Image& b, int c) {
    const double n = static_cast<double>(a.texelCount());
    double meanA = 0.0;
    double meanB = 0.0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            meanA += static_cast<double>(a.at(x, y, c));
            meanB += static_cast<double>(b.at(x, y, c));
        }
    meanA /= n;
    meanB /= n;
    double covariance = 0.0;
    double varianceA = 0.0;
    double varianceB = 0.0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const double da = static_cast<double>(a.at(x, y, c)) - meanA;
            const double db = static_cast<double>(b.at(x, y, c)) - meanB;
            covariance += da * db;
            varianceA += da * da;
            varianceB += db * db;
        }
    // A map whose values differ by float rounding only is flat: treat variances at that level as 0.
    const double tiny = 1e-12 * n;
    if (!(varianceA > tiny) || !(varianceB > tiny)) return {0.0, false};
    return {std::clamp(covariance / std::sqrt(varianceA * varianceB), -1.0, 1.0), true};
}

}  // namespace

ReliefTexture reliefFromPhoto(const Image& photo, const PhotoImportParams& params) {
    validate(photo, params);
    const Image luma = luminance(photo);

    // The four blurs of the band model (import.h); each from L directly, so no approximation error
    // accumulates from one to the next.
    const Image g0 = blurTile(luma, params.sigmaSmall);
    const Image g1 = blurTile(luma, params.sigmaMedium);
    const Image g2 = blurTile(luma, params.sigmaLarge);
    const Image g3 = blurTile(luma, params.sigmaHuge);

    // h = wS (g0 - g1) + wM (g1 - g2) + wL (g2 - g3), with the sign of `invert` folded in so that
    // the normalisation below always maps the highest point to h = 1, i.e. d = 0 (the top).
    const double sign = params.invert ? -1.0 : 1.0;
    const double ws = sign * params.weightSmall;
    const double wm = sign * params.weightMedium;
    const double wl = sign * params.weightLarge;
    Image height(photo.width(), photo.height(), 1);
    for (std::size_t i = 0; i < height.pixels().size(); ++i) {
        const auto b0 = static_cast<double>(g0.pixels()[i]);
        const auto b1 = static_cast<double>(g1.pixels()[i]);
        const auto b2 = static_cast<double>(g2.pixels()[i]);
        const auto b3 = static_cast<double>(g3.pixels()[i]);
        height.pixels()[i] = static_cast<float>(ws * (b0 - b1) + wm * (b1 - b2) + wl * (b2 - b3));
    }

    ReliefTexture relief;
    // A featureless photo has nothing to raise: flat at the top (h = 1, d = 0).
    relief.depth = heightToDepth(normalizeToUnit(height, 1.0f));
    relief.normal = normalsFromDepth(relief.depth, params.depthScale);
    relief.color = photoColor(photo);
    relief.depthScale = params.depthScale;
    return relief;
}

NormalConventionReport detectNormalConvention(const Image& normals, const Image& depth) {
    if (normals.empty()) invalid("normal map: the image is empty");
    if (normals.channels() < 3)
        invalid("normal map: needs 3 channels (x, y, z), got " + std::to_string(normals.channels()));
    if (depth.empty()) invalid("depth map: the image is empty");
    if (depth.channels() != 1) invalid("depth map: needs 1 channel, got " + std::to_string(depth.channels()));

    const Image sized = depth.width() == normals.width() && depth.height() == normals.height()
                            ? depth
                            : resample(depth, normals.width(), normals.height());
    // Any S > 0 gives the same signs; the default keeps the derived normals in the range real maps use.
    const Image derived = normalsFromDepth(sized, kDefaultDepthScale);
    const Correlation cx = pearson(normals, derived, 0);
    const Correlation cy = pearson(normals, derived, 1);

    NormalConventionReport report;
    report.correlationX = cx.r;
    report.correlationY = cy.r;
    report.threshold =
        std::max(kConventionCorrelationThreshold, 4.0 / std::sqrt(static_cast<double>(normals.texelCount())));
    const double t = report.threshold;
    const std::string rx = "(r = " + formatCorrelation(cx.r) + ")";
    const std::string ry = "(r = " + formatCorrelation(cy.r) + ")";

    const std::string needs = ", needs > " + formatCorrelation(t) + ")";
    const std::string rxNeeds = "(r = " + formatCorrelation(cx.r) + needs;
    const std::string ryNeeds = "(r = " + formatCorrelation(cy.r) + needs;

    report.convention = NormalConvention::Unknown;
    const Correlation depthSlopeX = pearson(derived, derived, 0);
    const Correlation depthSlopeY = pearson(derived, derived, 1);
    if (t >= 1.0) {
        report.summary = "unknown: " + std::to_string(normals.texelCount()) +
                         " texels are too few to tell the convention from chance";
    } else if (!depthSlopeX.defined && !depthSlopeY.defined) {
        report.summary = "unknown: the depth map is flat, so there is nothing to compare the normal map with";
    } else if (!depthSlopeX.defined) {
        report.summary = "unknown: the depth map has no slope along u, so x cannot be checked";
    } else if (!cx.defined) {
        report.summary = "unknown: the normal map's x is constant, so it cannot be checked";
    } else if (cx.r < -t) {
        report.summary = "unknown: x is opposite to the depth map's normals " + rx +
                         "; is the depth map a height map (white = high), or is x flipped?";
    } else if (cx.r <= t) {
        report.summary = "unknown: x does not follow the depth map's normals " + rxNeeds +
                         "; do the two maps describe the same relief?";
    } else if (!depthSlopeY.defined) {
        report.summary = "unknown: the depth map has no slope along v, so y cannot be checked";
    } else if (cy.r > t) {
        report.convention = NormalConvention::OpenGL;
        report.summary = "OpenGL (green up): y agrees with the depth map's normals " + ry;
    } else if (cy.r < -t) {
        report.convention = NormalConvention::DirectX;
        report.summary = "DirectX (green down): y is opposite to the depth map's normals " + ry;
    } else {
        report.summary =
            "unknown: y does not follow the depth map's normals " + ryNeeds + " although x does " + rx;
    }
    return report;
}

const char* toString(NormalConvention convention) {
    switch (convention) {
        case NormalConvention::OpenGL:
            return "OpenGL";
        case NormalConvention::DirectX:
            return "DirectX";
        case NormalConvention::Unknown:
            return "unknown";
    }
    return "unknown";
}

NormalYResolution resolveNormalY(const Image& normals, const Image& depth, NormalY setting, bool force,
                                 const std::string& label, const std::string& howToFix) {
    const NormalConventionReport report = detectNormalConvention(normals, depth);
    NormalYResolution result;
    if (setting == NormalY::Auto) {
        if (report.convention == NormalConvention::Unknown) {
            result.note = label + ": normal_y auto: " + report.summary + "; read as up (OpenGL)";
        } else {
            result.flipY = report.convention == NormalConvention::DirectX;
            result.note = label + ": normal_y auto: " + report.summary;
        }
        return result;
    }
    result.flipY = setting == NormalY::Down;
    const bool xFollows = report.correlationX > report.threshold;
    const double againstChoice = result.flipY ? report.correlationY : -report.correlationY;
    if (xFollows && againstChoice > kConventionContradiction) {
        const std::string chosen = result.flipY ? "down (DirectX)" : "up (OpenGL)";
        const std::string message = label + ": read as " + chosen + ", but its gradient says " +
                                    report.summary + ", more than " +
                                    formatCorrelation(kConventionContradiction) + " against; " + howToFix;
        if (!force) invalid(message);
        result.note = message + " (kept: forced)";
    }
    return result;
}

void checkNormalMapContent(const Image& encoded, const std::string& label) {
    if (encoded.empty() || encoded.channels() < 3) return;
    const double n = static_cast<double>(encoded.texelCount());
    double grey = 0.0;
    double inward = 0.0;
    double length = 0.0;
    for (int y = 0; y < encoded.height(); ++y)
        for (int x = 0; x < encoded.width(); ++x) {
            const float r = encoded.at(x, y, 0);
            const float g = encoded.at(x, y, 1);
            const float b = encoded.at(x, y, 2);
            const float tol = 0.5f / 255.0f;  // half a step of an 8-bit file: exactly equal once quantised
            if (std::abs(r - g) <= tol && std::abs(g - b) <= tol) grey += 1.0;
            const double nx = 2.0 * static_cast<double>(r) - 1.0;
            const double ny = 2.0 * static_cast<double>(g) - 1.0;
            const double nz = 2.0 * static_cast<double>(b) - 1.0;
            if (nz < 0.0) inward += 1.0;
            length += std::sqrt(nx * nx + ny * ny + nz * nz);
        }
    const auto percent = [&](double count) {
        return formatNumber(std::round(1000.0 * count / n) / 10.0) + " %";
    };
    if (grey >= 0.9 * n)
        invalid(label + ": not a normal map: " + percent(grey) +
                " of its texels are grey (r = g = b); is it a height or depth map?");
    if (inward > 0.25 * n)
        invalid(label + ": not a tangent-space normal map: " + percent(inward) +
                " of its normals point into the surface (z < 0); is it signed, black or empty?");
    const double meanLength = length / n;
    if (meanLength < 0.5 || meanLength > 1.5)
        invalid(label + ": not a normal map: the mean length of its normals is " +
                formatNumber(std::round(1000.0 * meanLength) / 1000.0) + ", not 1; is it signed or scaled?");
}

void checkDepthMapContent(const Image& encoded, const std::string& label) {
    if (encoded.empty() || encoded.channels() < 3) return;
    const double n = static_cast<double>(encoded.texelCount());
    double sumR = 0.0;
    double sumG = 0.0;
    double sumB = 0.0;
    double outward = 0.0;
    double length = 0.0;
    for (int y = 0; y < encoded.height(); ++y)
        for (int x = 0; x < encoded.width(); ++x) {
            const double r = static_cast<double>(encoded.at(x, y, 0));
            const double g = static_cast<double>(encoded.at(x, y, 1));
            const double b = static_cast<double>(encoded.at(x, y, 2));
            sumR += r;
            sumG += g;
            sumB += b;
            if (b > 0.5) outward += 1.0;
            length +=
                std::sqrt((2 * r - 1) * (2 * r - 1) + (2 * g - 1) * (2 * g - 1) + (2 * b - 1) * (2 * b - 1));
        }
    const double r = sumR / n;
    const double g = sumG / n;
    const double b = sumB / n;
    const double meanLength = length / n;
    if (b >= 0.75 && std::abs(r - 0.5) <= 0.15 && std::abs(g - 0.5) <= 0.15 && outward >= 0.99 * n &&
        meanLength >= 0.85 && meanLength <= 1.15)
        invalid(label + ": looks like a tangent-space normal map (mean r, g, b = " +
                formatNumber(std::round(100.0 * r) / 100.0) + ", " +
                formatNumber(std::round(100.0 * g) / 100.0) + ", " +
                formatNumber(std::round(100.0 * b) / 100.0) +
                "; unit-length normals), not a height or depth map; give it as the normal map");
}

}  // namespace strata
