#include "strata/gdm/mesostructure.h"

#include "strata/core/error.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

namespace strata {

namespace {

using glm::dvec2;
using glm::dvec3;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// x - round(x), in [-0.5, 0.5]: the offset to the nearest copy of something at 0 on the unit circle.
double wrapCentred(double x) {
    return x - std::floor(x + 0.5);
}

// splitmix64 (as the relief patterns): random choices that are the same on every platform.
std::uint64_t mix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

// A uniform double in [0, 1) for (seed, stream, index).
double hashUnit(std::uint32_t seed, std::uint64_t stream, std::uint64_t index) {
    const std::uint64_t h = mix64(mix64(mix64(seed) ^ stream) ^ index);
    return double(h >> 11) * 0x1.0p-53;
}

dvec3 mix(const dvec3& a, const dvec3& b, double t) {
    return a + (b - a) * std::clamp(t, 0.0, 1.0);
}

// Exact distance to a torus of major radius R and minor radius r around the axis through the origin along
// `axis` (unit).
double torusDistance(const dvec3& q, const dvec3& axis, double majorRadius, double minorRadius) {
    const double h = glm::dot(q, axis);
    const double radial = glm::length(q - h * axis);
    return std::hypot(radial - majorRadius, h) - minorRadius;
}

// Exact distance to the 2-D rounded box of half sizes `half` and corner radius `rounding` (<= both halves).
double roundedBoxDistance(const dvec2& q, const dvec2& half, double rounding) {
    const dvec2 d = glm::abs(q) - half + dvec2(rounding);
    return glm::length(glm::max(d, dvec2(0.0))) + std::min(std::max(d.x, d.y), 0.0) - rounding;
}

// ---------------------------------------------------------------------------------------------------------
// weave: plain weave, 2 warps (along u) and 2 wefts (along v) per tile, each passing over and under the
// yarns it crosses. Yarn centrelines are sine waves in z; cross-sections are ellipses of half-width a
// (across, horizontal) and half-height b (vertical), sheared along the centreline.
constexpr double kWeaveHeight = 0.25;
constexpr double kYarnHalfWidth = 0.2;     // a: yarns 0.4 wide on a 0.5 pitch leave 0.1 gaps
constexpr double kYarnHalfHeight = 0.045;  // b
// The centreline amplitude A. Two crossing yarns do not interpenetrate when, for offsets (du, dv) from the
// crossing within the footprints, A (cos 2 pi du + cos 2 pi dv) >= b (sqrt(1 - (dv/a)^2) + sqrt(1 -
// (du/a)^2)); the worst case (du = dv ~ 0.1) needs A >= 1.07 b. 1.29 b leaves a visible gap.
constexpr double kYarnAmplitude = 0.058;
constexpr double kYarnCentreZ = 0.115;  // z from 0.012 to 0.218 < H (1 - 1.5 / 16) = 0.2266

// A yarn along `alongU ? u : v` at `across` = (v or u) position `offset`, centreline z = zc + sign A sin(2 pi
// t). The function g = sqrt((s / a)^2 + ((z - c(t)) / b)^2) - 1 has the yarn as its zero set; its gradient
// is at most sqrt(1 + c'^2) / min(a, b) with |c'| <= 2 pi A, so g min(a, b) / sqrt(1 + (2 pi A)^2) is a
// 1-Lipschitz bound (not the exact distance: the ellipse has none in closed form).
MesostructurePart yarn(std::string name, int material, bool alongU, double offset, double sign,
                       dvec3 colour) {
    const double scale =
        std::min(kYarnHalfWidth, kYarnHalfHeight) / std::sqrt(1.0 + std::pow(kTwoPi * kYarnAmplitude, 2.0));
    MesostructurePart part;
    part.name = std::move(name);
    part.material = material;
    part.distance = [=](const dvec3& p) {
        const double t = alongU ? p.x : p.y;
        const double s = wrapCentred((alongU ? p.y : p.x) - offset);
        const double dz = p.z - (kYarnCentreZ + sign * kYarnAmplitude * std::sin(kTwoPi * t));
        return (std::hypot(s / kYarnHalfWidth, dz / kYarnHalfHeight) - 1.0) * scale;
    };
    part.albedo = [=](const dvec3& p) {
        // Fibres twisted around the yarn: fine diagonal stripes, and darker towards its flanks.
        const double t = alongU ? p.x : p.y;
        const double s = wrapCentred((alongU ? p.y : p.x) - offset) / kYarnHalfWidth;
        const double fibre = 0.88 + 0.12 * std::sin(kTwoPi * (14.0 * t + 1.5 * s));
        const double flank = 1.0 - 0.35 * s * s;
        return colour * (fibre * flank);
    };
    return part;
}

std::vector<MesostructurePart> makeWeave() {
    const dvec3 warp(0.16, 0.24, 0.52);  // indigo
    const dvec3 weft(0.86, 0.78, 0.58);  // cream
    std::vector<MesostructurePart> parts;
    // Warp j at v = 0.25 + 0.5 j rises over weft i at u = 0.25 + 0.5 i when i == j, and passes under it
    // otherwise; weft i does the opposite, so each crossing has one yarn on top.
    for (int j = 0; j < 2; ++j)
        parts.push_back(
            yarn("warp " + std::to_string(j), 0, true, 0.25 + 0.5 * j, j == 0 ? 1.0 : -1.0, warp));
    for (int i = 0; i < 2; ++i)
        parts.push_back(
            yarn("weft " + std::to_string(i), 1, false, 0.25 + 0.5 * i, i == 0 ? -1.0 : 1.0, weft));
    return parts;
}

// ---------------------------------------------------------------------------------------------------------
// chain: two chains along u per tile (v = 0.25, 0.75), four round links each, alternately lying flat (axis
// z) and standing (axis v), every link through its two neighbours, as chain mail. Exact torus distances; a
// torus around a coordinate axis is nearer the closer its centre in |du| and in |dv|, so the nearest copy
// of each link (wrapCentred) gives the exact periodic distance.
constexpr double kChainHeight = 0.5;
constexpr double kLinkMajor = 0.17;  // R: links 0.25 apart interlock when R > 0.125 + r
constexpr double kLinkMinor = 0.03;  // r
constexpr double kStandingZ = 0.21;  // standing links span z 0.01 .. 0.41 < H (1 - 1.5 / 16) = 0.453
constexpr double kFlatZ = 0.16;      // flat links hang lower, still through the standing links' holes

std::vector<MesostructurePart> makeChain() {
    std::vector<MesostructurePart> parts;
    const dvec3 steel(0.62, 0.62, 0.60);
    const dvec3 brass(0.78, 0.62, 0.32);
    for (int c = 0; c < 2; ++c) {
        const double v = 0.25 + 0.5 * c;
        for (int k = 0; k < 4; ++k) {
            // The second chain is shifted by one link, so flat and standing links alternate across chains.
            const double u = 0.125 + 0.25 * k + 0.25 * c;
            const bool standing = (k % 2) == 1;
            const dvec3 centre(u, v, standing ? kStandingZ : kFlatZ);
            const dvec3 axis = standing ? dvec3(0.0, 1.0, 0.0) : dvec3(0.0, 0.0, 1.0);
            MesostructurePart part;
            part.name = "link " + std::to_string(4 * c + k);
            part.material = standing ? 1 : 0;
            part.distance = [=](const dvec3& p) {
                const dvec3 q(wrapCentred(p.x - centre.x), wrapCentred(p.y - centre.y), p.z - centre.z);
                return torusDistance(q, axis, kLinkMajor, kLinkMinor);
            };
            const dvec3 colour = standing ? brass : steel;
            part.albedo = [=](const dvec3&) { return colour; };
            parts.push_back(std::move(part));
        }
    }
    return parts;
}

// ---------------------------------------------------------------------------------------------------------
// grid: the vase's lattice (Fig. 9a): round rods along u in a lower layer, rods along v in an upper layer
// resting on them (fused 0.015 deep), open square holes between. Exact cylinder distances; the nearest copy
// (wrapCentred) is the nearest rod.
constexpr double kGridHeight = 0.25;
constexpr double kRodRadius = 0.055;
constexpr double kLowerRodZ = 0.065;  // z from 0.01
constexpr double kUpperRodZ = 0.16;   // to 0.215 < H (1 - 1.5 / 16) = 0.2266

std::vector<MesostructurePart> makeGrid() {
    std::vector<MesostructurePart> parts;
    const dvec3 lower(0.70, 0.38, 0.24);  // terracotta
    const dvec3 upper(0.82, 0.56, 0.36);
    for (int layer = 0; layer < 2; ++layer) {
        for (int n = 0; n < 2; ++n) {
            const bool alongU = layer == 0;
            const double offset = 0.25 + 0.5 * n;
            const double zc = alongU ? kLowerRodZ : kUpperRodZ;
            MesostructurePart part;
            part.name = std::string(alongU ? "lower rod " : "upper rod ") + std::to_string(n);
            part.material = layer;
            part.distance = [=](const dvec3& p) {
                return std::hypot(wrapCentred((alongU ? p.y : p.x) - offset), p.z - zc) - kRodRadius;
            };
            const dvec3 colour = alongU ? lower : upper;
            part.albedo = [=](const dvec3&) { return colour; };
            parts.push_back(std::move(part));
        }
    }
    return parts;
}

// ---------------------------------------------------------------------------------------------------------
// scales: the dinosaur's squamae (Fig. 9d). Four rows along u (v = 0.125 + 0.25 k), two round scales per
// row, alternate rows shifted by a quarter tile; each scale a thin disc tilted 20 degrees about u so that it
// rises towards +v and its free rim lies over the base of the next row (parallel planes 0.085 apart, discs
// 0.024 thick: they overlap in plan and never touch). On a thin skin at the bottom. Exact distance to a
// rounded disc (rigidly moved); the nearest copy of a tilted disc need not be the nearest surface, so all
// nine copies around the tile are visited, those whose bounding sphere is farther than the best skipped.
constexpr double kScalesHeight = 0.25;
constexpr double kScaleRadius = 0.245;
constexpr double kScaleHalfThickness = 0.012;
constexpr double kScaleTilt = 20.0 * std::numbers::pi / 180.0;
constexpr double kScaleCentreZ = 0.1;  // z from 0.005 to 0.195 < H (1 - 1.5 / 16) = 0.2266
constexpr double kSkinThickness = 0.012;

double discDistance(const dvec3& q, const dvec3& normal, double radius, double halfThickness) {
    constexpr double kRounding = 0.008;
    const double h = glm::dot(q, normal);
    const double radial = glm::length(q - h * normal);
    return roundedBoxDistance(dvec2(radial, h), dvec2(radius, halfThickness), kRounding);
}

std::vector<MesostructurePart> makeScales(std::uint32_t seed) {
    std::vector<MesostructurePart> parts;
    const dvec3 normal(0.0, -std::sin(kScaleTilt), std::cos(kScaleTilt));
    const dvec3 upSlope(0.0, std::cos(kScaleTilt), std::sin(kScaleTilt));  // in the disc, towards its rim
    MesostructurePart skin;
    skin.name = "skin";
    skin.material = 0;
    skin.distance = [](const dvec3& p) {
        return std::abs(p.z - 0.5 * kSkinThickness) - 0.5 * kSkinThickness;
    };
    skin.albedo = [](const dvec3&) { return dvec3(0.10, 0.12, 0.07); };
    parts.push_back(std::move(skin));
    for (int row = 0; row < 4; ++row) {
        for (int n = 0; n < 2; ++n) {
            const dvec3 centre(0.25 + 0.5 * n + 0.25 * (row % 2), 0.125 + 0.25 * row, kScaleCentreZ);
            const double tint = 0.85 + 0.3 * hashUnit(seed, 1, std::uint64_t(2 * row + n));
            MesostructurePart part;
            part.name = "scale " + std::to_string(2 * row + n);
            part.material = 1;
            part.distance = [=](const dvec3& p) {
                const dvec3 q0(wrapCentred(p.x - centre.x), wrapCentred(p.y - centre.y), p.z - centre.z);
                double best = discDistance(q0, normal, kScaleRadius, kScaleHalfThickness);
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        if (dx == 0 && dy == 0) continue;
                        const dvec3 q = q0 + dvec3(dx, dy, 0.0);
                        if (glm::length(q) - (kScaleRadius + kScaleHalfThickness) >= best) continue;
                        best = std::min(best, discDistance(q, normal, kScaleRadius, kScaleHalfThickness));
                    }
                return best;
            };
            part.albedo = [=](const dvec3& p) {
                // Dark at the attached base, bright bronze-green towards the free rim.
                const dvec3 q(wrapCentred(p.x - centre.x), wrapCentred(p.y - centre.y), p.z - centre.z);
                const double s = glm::dot(q, upSlope) / kScaleRadius;
                return mix(dvec3(0.12, 0.20, 0.10), dvec3(0.55, 0.60, 0.28), 0.5 * (s + 1.0)) * tint;
            };
            parts.push_back(std::move(part));
        }
    }
    return parts;
}

// ---------------------------------------------------------------------------------------------------------
// bark: Fig. 10's tree bark. Three ridges per tile run along v and meander in u; each is a wide cap on a
// narrow stem, so the cap overhangs a deep undercut on both sides (no height field has that), and cracks
// across the ridges break them into plates. On a layer of inner bark. The ridge's cross-section in (x, z),
// x = u - m(v), is a union of exact 2-D box distances whose sizes (cap half-width w(v), top t(v)) vary along
// v; d/dv of that is at most |m'| + |w'| + |t'| = S, so the 3-D gradient is at most sqrt(1 + S^2), and the
// profile distance divided by it is a 1-Lipschitz bound. The cracks are subtracted with max(d, -crack).
constexpr double kBarkHeight = 0.25;
constexpr double kInnerBark = 0.03;  // the base layer's thickness
constexpr double kStemHalfWidth = 0.035;
constexpr double kCapBottom = 0.1;  // the undercut: from the base to here, only the stem
constexpr double kCapTop = 0.19;    // mean top, +- kCapTopWave: at most 0.205 < H (1 - 1.5 / 16) = 0.2266
constexpr double kCapTopWave = 0.015;
constexpr double kCapHalfWidth = 0.115;  // +- kCapWidthWave
constexpr double kCapWidthWave = 0.02;
constexpr double kMeander1 = 0.03;   // u amplitude of the meander's first harmonic
constexpr double kMeander2 = 0.015;  // and of its second
constexpr double kCrackHalfWidth = 0.018;

std::vector<MesostructurePart> makeBark(std::uint32_t seed) {
    std::vector<MesostructurePart> parts;
    MesostructurePart inner;
    inner.name = "inner bark";
    inner.material = 0;
    inner.distance = [](const dvec3& p) { return std::abs(p.z - 0.5 * kInnerBark) - 0.5 * kInnerBark; };
    inner.albedo = [](const dvec3&) { return dvec3(0.22, 0.13, 0.07); };
    parts.push_back(std::move(inner));

    const double slope =
        kTwoPi * (kMeander1 + 2.0 * kMeander2) + kTwoPi * 2.0 * kCapWidthWave + kTwoPi * 3.0 * kCapTopWave;
    const double scale = 1.0 / std::sqrt(1.0 + slope * slope);
    for (int r = 0; r < 3; ++r) {
        const auto random = [&](int k) { return hashUnit(seed, 2, std::uint64_t(16 * r + k)); };
        const double u0 = (r + 0.5) / 3.0 + 0.03 * (random(0) - 0.5);
        const double phase1 = kTwoPi * random(1);
        const double phase2 = kTwoPi * random(2);
        const double phaseWidth = kTwoPi * random(3);
        const double phaseTop = kTwoPi * random(4);
        // Two cracks per ridge, at random heights along v.
        const double crack0 = random(5);
        const double crack1 = crack0 + 0.3 + 0.4 * random(6);
        const auto centreU = [=](double v) {
            return u0 + kMeander1 * std::sin(kTwoPi * v + phase1) +
                   kMeander2 * std::sin(2.0 * kTwoPi * v + phase2);
        };
        MesostructurePart part;
        part.name = "ridge " + std::to_string(r);
        part.material = 1;
        part.distance = [=](const dvec3& p) {
            const double x = wrapCentred(p.x - centreU(p.y));
            const double halfWidth =
                kCapHalfWidth + kCapWidthWave * std::sin(2.0 * kTwoPi * p.y + phaseWidth);
            const double top = kCapTop + kCapTopWave * std::sin(3.0 * kTwoPi * p.y + phaseTop);
            const double stem = roundedBoxDistance(dvec2(x, p.z - 0.5 * kCapBottom - 0.01),
                                                   dvec2(kStemHalfWidth, 0.5 * kCapBottom + 0.01), 0.0);
            const double cap = roundedBoxDistance(dvec2(x, p.z - 0.5 * (kCapBottom + top)),
                                                  dvec2(halfWidth, 0.5 * (top - kCapBottom)), 0.03);
            const double crack =
                std::min(std::abs(wrapCentred(p.y - crack0)), std::abs(wrapCentred(p.y - crack1))) -
                kCrackHalfWidth;
            return std::max(std::min(stem, cap) * scale, -crack);
        };
        part.albedo = [=](const dvec3& p) {
            // Grey-brown plates, lighter where weathered on top, with fine vertical fibres.
            const double x = wrapCentred(p.x - centreU(p.y));
            const double fibre = 0.9 + 0.1 * std::sin(kTwoPi * 60.0 * x);
            const double weathered = std::clamp((p.z - kCapBottom) / (kCapTop - kCapBottom), 0.0, 1.0);
            return mix(dvec3(0.30, 0.21, 0.13), dvec3(0.66, 0.60, 0.52), weathered) * fibre;
        };
        parts.push_back(std::move(part));
    }
    return parts;
}

struct Entry {
    MesostructureInfo info;
    std::vector<MesostructurePart> (*make)(std::uint32_t seed);
};

// The order is part of the interface (`strata meso --list`, docs/gdm.md). Append; do not reorder.
const std::vector<Entry>& registry() {
    static const std::vector<Entry> entries{
        {{"weave", "plain weave: warps and wefts passing over and under each other, elliptic yarns",
          kWeaveHeight},
         [](std::uint32_t) { return makeWeave(); }},
        {{"chain", "chain mail: round links alternately flat and standing, each through its neighbours",
          kChainHeight},
         [](std::uint32_t) { return makeChain(); }},
        {{"grid", "a lattice of round rods in two layers with open square holes (the paper's vase)",
          kGridHeight},
         [](std::uint32_t) { return makeGrid(); }},
        {{"scales", "overlapping tilted round scales in offset rows on a thin skin (squamae)", kScalesHeight},
         makeScales},
        {{"bark", "ridged bark: meandering ridges with overhanging caps over deep undercuts, cracked",
          kBarkHeight},
         makeBark},
    };
    return entries;
}

}  // namespace

Mesostructure::Mesostructure(std::string name, double designHeight, double height,
                             std::vector<MesostructurePart> parts)
    : mName(std::move(name)), mHeight(height), mParts(std::move(parts)) {
    if (!(std::isfinite(designHeight) && designHeight > 0.0) || !(std::isfinite(height) && height > 0.0))
        throw Error(ErrorKind::InvalidInput,
                    "mesostructure " + mName + ": the height H must be a number > 0, got " +
                        formatNumber(height) + " (designed for " + formatNumber(designHeight) + ")");
    if (mParts.empty()) throw Error(ErrorKind::InvalidInput, "mesostructure " + mName + ": it has no parts");
    mStretch = height / designHeight;
    mDistanceScale = std::min(1.0, mStretch);
}

dvec3 Mesostructure::toDesign(const dvec3& p) const {
    return {p.x - std::floor(p.x), p.y - std::floor(p.y), p.z / mStretch};
}

double Mesostructure::distance(const dvec3& p) const {
    const dvec3 q = toDesign(p);
    double best = std::numeric_limits<double>::infinity();
    for (const MesostructurePart& part : mParts) best = std::min(best, part.distance(q));
    return best * mDistanceScale;
}

double Mesostructure::partDistance(int k, const dvec3& p) const {
    return part(k).distance(toDesign(p)) * mDistanceScale;
}

MesostructureSample Mesostructure::sample(const dvec3& p) const {
    const dvec3 q = toDesign(p);
    MesostructureSample result;
    result.distance = std::numeric_limits<double>::infinity();
    for (int k = 0; k < partCount(); ++k) {
        const double d = part(k).distance(q);
        if (d < result.distance) {
            result.distance = d;
            result.part = k;
        }
    }
    const MesostructurePart& nearest = part(result.part);
    result.distance *= mDistanceScale;
    result.albedo = glm::clamp(nearest.albedo(q), dvec3(0.0), dvec3(1.0));
    result.material = nearest.material;
    return result;
}

dvec3 Mesostructure::normal(const dvec3& p, double h) const {
    const dvec3 g(distance(p + dvec3(h, 0, 0)) - distance(p - dvec3(h, 0, 0)),
                  distance(p + dvec3(0, h, 0)) - distance(p - dvec3(0, h, 0)),
                  distance(p + dvec3(0, 0, h)) - distance(p - dvec3(0, 0, h)));
    const double length = glm::length(g);
    return length > 0.0 ? g / length : dvec3(0.0, 0.0, 1.0);
}

const std::vector<MesostructureInfo>& mesostructureList() {
    static const std::vector<MesostructureInfo> list = [] {
        std::vector<MesostructureInfo> infos;
        for (const Entry& entry : registry()) infos.push_back(entry.info);
        return infos;
    }();
    return list;
}

Mesostructure makeMesostructure(const std::string& name, const MesostructureParams& params) {
    const auto& entries = registry();
    const auto it = std::find_if(entries.begin(), entries.end(),
                                 [&](const Entry& entry) { return entry.info.name == name; });
    if (it == entries.end()) {
        std::string names;
        for (const Entry& entry : entries) names += (names.empty() ? "" : ", ") + entry.info.name;
        throw Error(ErrorKind::InvalidInput,
                    "unknown mesostructure \"" + name + "\" (the built-ins are " + names + ")");
    }
    if (!(std::isfinite(params.height) && params.height >= 0.0))
        throw Error(ErrorKind::InvalidInput, "mesostructure " + name +
                                                 ": the height H must be a number > 0, got " +
                                                 formatNumber(params.height));
    const double height = params.height == 0.0 ? it->info.defaultHeight : params.height;
    return Mesostructure(name, it->info.defaultHeight, height, it->make(params.seed));
}

}  // namespace strata
