// Internal: one direction's geometry in texel space, and the exact horizon of a texel along its own
// line through the bilinear relief. Shared by the brute-force search and the sweep's near field.
#pragma once

#include "strata/image/image.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace strata::detail {

// Direction phi (in the (u, v) plane, from +u towards +v) on a W x H map. A point at distance t (tile
// widths) from texel centre (x, y) in that direction is at texel coordinates (x + vx t, y + vy t),
// vx = W cos phi, vy = -H sin phi (v is up, rows go down). The major axis is the one the line crosses
// faster; walking from a texel towards the direction meets the major axis' texel centres ("columns",
// rows when the major axis is y) every dt tile widths, and the minor coordinate moves by g per column.
struct LineDirection {
    double cosPhi = 1.0;
    double sinPhi = 0.0;
    bool xMajor = true;
    int step = 1;     // +1 or -1: the major texel index walking towards the direction
    double g = 0.0;   // minor coordinate per major step walking towards the direction, |g| <= 1
    double dt = 0.0;  // tile widths per major step
    int sideX = 1;    // neighbour that the direction enters first, for the t -> 0+ slope
    int sideY = 1;

    LineDirection(double phi, int width, int height) {
        cosPhi = std::cos(phi);
        sinPhi = std::sin(phi);
        const double vx = cosPhi * width;
        const double vy = -sinPhi * height;
        xMajor = std::abs(vx) >= std::abs(vy);
        const double va = xMajor ? vx : vy;
        const double vb = xMajor ? vy : vx;
        step = va > 0.0 ? 1 : -1;
        g = vb / std::abs(va);
        dt = 1.0 / std::abs(va);
        sideX = vx > 0.0 ? 1 : -1;
        sideY = vy > 0.0 ? 1 : -1;
    }
};

// Depth access in (major, minor) coordinates with wrap-around.
class MajorMinorDepth {
public:
    MajorMinorDepth(const Image& depth, bool xMajor)
        : mData(depth.pixels().data()), mWidth(depth.width()), mHeight(depth.height()), mXMajor(xMajor) {}

    int majorSize() const { return mXMajor ? mWidth : mHeight; }
    int minorSize() const { return mXMajor ? mHeight : mWidth; }
    // Depth at (major a, minor b), both already wrapped into range.
    float at(int a, int b) const {
        return mXMajor ? mData[static_cast<std::size_t>(b) * static_cast<std::size_t>(mWidth) +
                               static_cast<std::size_t>(a)]
                       : mData[static_cast<std::size_t>(a) * static_cast<std::size_t>(mWidth) +
                               static_cast<std::size_t>(b)];
    }
    static int wrap(int i, int n) {
        const int r = i % n;
        return r < 0 ? r + n : r;
    }
    // Linear interpolation along the minor axis at integer major a (any integer) and real minor b.
    double column(int a, double b) const {
        const double fb = std::floor(b);
        const double f = b - fb;
        const int aw = wrap(a, majorSize());
        const int b0 = wrap(static_cast<int>(fb), minorSize());
        const int b1 = b0 + 1 == minorSize() ? 0 : b0 + 1;
        return (1.0 - f) * static_cast<double>(at(aw, b0)) + f * static_cast<double>(at(aw, b1));
    }

private:
    const float* mData;
    int mWidth;
    int mHeight;
    bool mXMajor;
};

// Raises `best` (a tan h) to the largest elevation (z(t) - zP) / t of the quadratic arc through
// (t0, z0) and (t1, z1) with z''/2 = curvature / (t1 - t0)^2: the bilinear relief along a line inside
// one cell is such an arc (curvature = -S e da db, e the cell's twist d00 - d10 - d01 + d11 and da, db
// the extents of the segment in the cell's two axes). Endpoints are handled by the caller.
// Real is float (the sweep) or double (the exact walk).
template <typename Real>
void raiseByArcInterior(Real& best, Real zP, Real t0, Real z0, Real t1, Real z1, Real curvature) {
    if (curvature >= Real(0)) return;  // a convex arc has no interior maximum of the elevation
    const Real length = t1 - t0;
    const Real c = curvature / (length * length);
    const Real b = (z1 - z0) / length - c * (t0 + t1);
    const Real a = z0 - b * t0 - c * t0 * t0;  // z(t) = a + b t + c t^2
    // d/dt ((z - zP) / t) = 0  <=>  c t^2 = a - zP, where the elevation (a - zP) / t + b + c t is
    // b - 2 sqrt((a - zP) c).
    const Real ratio = (a - zP) / c;
    if (ratio <= Real(0)) return;
    const Real t = std::sqrt(ratio);
    if (t > t0 && t < t1) best = std::max(best, b - Real(2) * std::sqrt((a - zP) * c));
}

// The exact horizon tan h >= 0 of texel (x, y) along its own line in direction `dir`, over distances
// t in (0, tMax], for the bilinear relief z = -scale d. Walks cell by cell: every major texel centre,
// every minor grid crossing, the quadratic arc inside each cell, the t -> 0+ slope, and the point at
// tMax. Stops early once nothing can rise higher: every depth is >= minDepth.
inline double horizonAlongLine(const Image& depth, const MajorMinorDepth& grid, const LineDirection& dir,
                               int x, int y, double scale, double tMax, double minDepth, double best = 0.0) {
    const int w = depth.width();
    const int h = depth.height();
    const double d0 = depth.at(x, y);
    const double zP = -scale * d0;
    // The limit t -> 0+: the slope of the cell the direction enters (its depth along the line is
    // d0 + t (|vx| (dX - d0) + |vy| (dY - d0)) + O(t^2)).
    const double dX = depth.at(MajorMinorDepth::wrap(x + dir.sideX, w), y);
    const double dY = depth.at(x, MajorMinorDepth::wrap(y + dir.sideY, h));
    best =
        std::max(best, scale * (std::abs(dir.cosPhi) * w * (d0 - dX) + std::abs(dir.sinPhi) * h * (d0 - dY)));
    const double rise = scale * (d0 - minDepth);
    const int a0 = dir.xMajor ? x : y;
    const double b0 = dir.xMajor ? y : x;
    double tPrev = 0.0;
    double zPrev = zP;
    double bPrev = b0;
    for (int q = 1;; ++q) {
        double t = q * dir.dt;
        const bool last = t >= tMax;
        double frac = 1.0;  // of this major step that lies within tMax
        if (last) {
            frac = (tMax - tPrev) / dir.dt;
            t = tMax;
        }
        if (rise <= best * tPrev) break;
        const int aPrev = a0 + dir.step * (q - 1);
        const int a = aPrev + dir.step;
        const double b = bPrev + dir.g * frac;
        // A minor grid line crossed between bPrev and b splits the step into two cells.
        const double lo = std::min(bPrev, b);
        const double hi = std::max(bPrev, b);
        const double n = std::ceil(lo);
        double segT0 = tPrev;
        double segZ0 = zPrev;
        double segB0 = bPrev;
        double segA0 = 0.0;  // position within the major step, 0..frac
        auto finishSegment = [&](double segA1, double segB1, double segT1, double segZ1) {
            // The cell of this segment: major cell [aPrev, a] (0..1 within it), minor cell floor(mid).
            const double mid = 0.5 * (segB0 + segB1);
            const double cellB = std::floor(mid);
            const double e = grid.column(aPrev, cellB) - grid.column(a, cellB) -
                             grid.column(aPrev, cellB + 1) + grid.column(a, cellB + 1);
            const double curvature = -scale * e * (segA1 - segA0) * (segB1 - segB0);
            raiseByArcInterior(best, zP, segT0, segZ0, segT1, segZ1, curvature);
            best = std::max(best, (segZ1 - zP) / segT1);
            segT0 = segT1;
            segZ0 = segZ1;
            segB0 = segB1;
            segA0 = segA1;
        };
        if (n < hi && n > lo) {
            const double f = (n - bPrev) / (b - bPrev);  // of the (partial) step
            const double tc = tPrev + f * (t - tPrev);
            const double fa = f * frac;
            const int in = static_cast<int>(n);
            // On the minor grid line the relief is linear along the major axis.
            const double zc = -scale * ((1.0 - fa) * grid.column(aPrev, in) + fa * grid.column(a, in));
            finishSegment(fa, n, tc, zc);
        }
        double zEnd;
        if (frac == 1.0) {
            zEnd = -scale * grid.column(a, b);
        } else {
            // The point at tMax, inside the step: bilinear.
            const double fb = std::floor(b);
            const double fbv = b - fb;
            const double top = (1.0 - frac) * grid.column(aPrev, fb) + frac * grid.column(a, fb);
            const double bottom = (1.0 - frac) * grid.column(aPrev, fb + 1) + frac * grid.column(a, fb + 1);
            zEnd = -scale * ((1.0 - fbv) * top + fbv * bottom);
        }
        finishSegment(frac, b, t, zEnd);
        tPrev = t;
        zPrev = zEnd;
        bPrev = b;
        if (last) break;
    }
    return best;
}

}  // namespace strata::detail
