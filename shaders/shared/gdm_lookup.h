// The GDM lookup d(T, V) of the paper's per-pixel algorithm (Wang et al. 2004, Sec. 3.2), written once for
// the OpenGL renderer (shaders/gdm/gdm.frag.glsl) and the CPU emulation (emulateGdm, src/gdm/gdm_trace.cpp),
// so that the two compute the same thing in the same float arithmetic (strata/gdm/gdm_trace.h documents the
// rule; CONVENTIONS §8 the sampling).
//
// The includer supplies the fetch gdmValue(i, j, k, t, s): the substituted value at voxel (i, j, k) and
// direction sample (t, s), a raw miss read as the distance to the slab's boundary (gdmBoundaryDistance) and
// an SVD's value reconstructed (gdm_svd.h).
#ifdef __cplusplus
#pragma once
#endif
#include "prelude.h"

STRATA_SHARED_BEGIN

// The sampling of a GDM, as the lookup needs it.
struct GdmLookupParams {
    ivec3 voxels;      // Nx, Ny, Nz
    ivec2 directions;  // Ntheta, Nphi
    float height;      // H, tile widths
    float tolerance;   // the exit rule's, tile widths along the ray
    bool bilinear;     // directions bilinear between four samples; false: the nearest sample
};

// Distance from the centre of voxel layer k along direction sample t to the slab boundary it leaves
// through: (H - z) / cos(theta) going up, z / -cos(theta) going down (gdm_svd.h's, in float).
STRATA_SHARED_FUNCTION float gdmBoundaryDistance(GdmLookupParams p, int k, int t) {
    float z = (float(k) + 0.5f) * p.height / float(p.voxels.z);
    float c = cos((float(t) + 0.5f) * 3.14159265358979f / float(p.directions.x));
    return c > 0.0f ? (p.height - z) / c : z / -c;
}

// i modulo n in [0, n), for any sign of i (GLSL's % is undefined for negative operands).
STRATA_SHARED_FUNCTION int gdmWrap(int i, int n) {
    int r = i - (i / n) * n;
    return r < 0 ? r + n : r;
}

STRATA_SHARED_CLASS_BEGIN(GdmLookup)
STRATA_SHARED_FETCH(float gdmValue(int i, int j, int k, int t, int s))

// d(point, direction) at a point of the isotropic texture frame (u, v, w H), for a unit direction: x = the
// distance, y = 1 for an exit (dmax, x = 1e30). Trilinear over the voxel centres (wrapping in u, v, clamped
// in w); in (theta, phi) the nearest sample, or bilinear between the four sample centres around it (theta
// clamped, phi wrapping). The same weights mix the boundary distances b, and the value is an exit iff
// d >= b - tolerance. Corners whose value is below dropBelow are left out (the rest keep their weights: only
// the ratio of d to b matters); none left is a hit at distance 0.
STRATA_SHARED_FUNCTION vec2 gdmLookup(GdmLookupParams p, vec3 point, vec3 direction, float dropBelow) {
    const float kPi = 3.14159265358979f;
    float theta = acos(clamp(direction.z, -1.0f, 1.0f));
    float phi = atan(direction.y, direction.x);
    if (phi < 0.0f) phi += 2.0f * kPi;
    int tapT[4];
    int tapS[4];
    float tapWeight[4];
    int taps = 0;
    if (!p.bilinear) {
        tapT[0] = clamp(int(theta / kPi * float(p.directions.x)), 0, p.directions.x - 1);
        tapS[0] = clamp(int(phi / (2.0f * kPi) * float(p.directions.y)), 0, p.directions.y - 1);
        tapWeight[0] = 1.0f;
        taps = 1;
    } else {
        float ft = clamp(theta / kPi * float(p.directions.x) - 0.5f, 0.0f, float(p.directions.x - 1));
        float fs = phi / (2.0f * kPi) * float(p.directions.y) - 0.5f;
        float t0 = floor(ft);
        float s0 = floor(fs);
        float at = ft - t0;
        float as = fs - s0;
        for (int corner = 0; corner < 4; ++corner) {
            int dt = corner & 1;
            int ds = corner >> 1;
            float weight = (dt == 1 ? at : 1.0f - at) * (ds == 1 ? as : 1.0f - as);
            if (weight == 0.0f) continue;
            tapT[taps] = min(int(t0) + dt, p.directions.x - 1);
            tapS[taps] = gdmWrap(int(s0) + ds, p.directions.y);
            tapWeight[taps] = weight;
            ++taps;
        }
    }
    float fx = point.x * float(p.voxels.x) - 0.5f;
    float fy = point.y * float(p.voxels.y) - 0.5f;
    float fz = clamp(point.z / p.height * float(p.voxels.z) - 0.5f, 0.0f, float(p.voxels.z - 1));
    float x0 = floor(fx);
    float y0 = floor(fy);
    float z0 = floor(fz);
    float ax = fx - x0;
    float ay = fy - y0;
    float az = fz - z0;
    // The tile wraps: only x0 and y0 modulo the grid matter (and tile coordinates on a mesh reach thousands).
    int xi = gdmWrap(int(x0 - floor(x0 / float(p.voxels.x)) * float(p.voxels.x)), p.voxels.x);
    int yi = gdmWrap(int(y0 - floor(y0 / float(p.voxels.y)) * float(p.voxels.y)), p.voxels.y);
    float d = 0.0f;
    float b = 0.0f;
    float total = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
        int dx = corner & 1;
        int dy = (corner >> 1) & 1;
        int dz = corner >> 2;
        float weight = (dx == 1 ? ax : 1.0f - ax) * (dy == 1 ? ay : 1.0f - ay) * (dz == 1 ? az : 1.0f - az);
        if (weight == 0.0f) continue;
        int i = gdmWrap(xi + dx, p.voxels.x);
        int j = gdmWrap(yi + dy, p.voxels.y);
        int k = min(int(z0) + dz, p.voxels.z - 1);
        for (int tap = 0; tap < taps; ++tap) {
            float value = gdmValue(i, j, k, tapT[tap], tapS[tap]);
            if (value < dropBelow) continue;
            float w = weight * tapWeight[tap];
            d += w * value;
            b += w * gdmBoundaryDistance(p, k, tapT[tap]);
            total += w;
        }
    }
    if (total == 0.0f) return vec2(0.0f, 0.0f);
    if (d >= b - p.tolerance) return vec2(1e30f, 1.0f);
    return vec2(max(d, 0.0f), 0.0f);
}
STRATA_SHARED_CLASS_END

STRATA_SHARED_END
