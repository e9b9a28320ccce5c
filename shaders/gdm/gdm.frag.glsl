#version 450 core
// Fragment stage of the GDM program: the paper's per-pixel algorithm (Sec. 3.2, "PixelShading"), as
// emulateGdm (src/gdm/gdm_trace.cpp) runs it on the CPU.
//
// The fragment lies on the face through which the pixel's ray enters its prism (back faces are culled): T_in
// is its interpolated texture position. The exit point is the nearest other face of the prism along the
// ray, found by ray / triangle intersection with the prism's 8 triangles (the fins split as the shell splits
// them; exact where the paper intersects planes), and T_out is the hit triangle's texture positions
// interpolated at it. With dt = |T_out - T_in| and V = (T_out - T_in) / dt in the isotropic frame, the GDM
// gives d = d(T_in, V); d < dt (and not an exit) is a hit at T = T_in + d V, whose world position,
// P_in + d / dt (P_out - P_in), sets the depth. Otherwise the fragment is discarded: the prism the ray goes
// on into draws its own entry face.
//
// The GDM lookup is emulateGdm's: trilinear over the voxel centres (wrapping in u, v, clamped in w), the
// nearest direction sample or bilinear between four, on substituted values (a raw miss counts as the
// distance to the slab's boundary, gdm_svd.h), the exit rule d >= b - tolerance on the same mix of
// boundary distances. Values come from the raw GDM or from the SVD's maps, in storage buffers laid out as
// their files are (gdm_asset.h): W rows x rank, E rank x cols, the paper's layout (rows (x, y, phi),
// columns (theta, z)).
//
// Outputs (uOutput): 0 uvw: (u, v modulo 1, w, 1); 1 shadow: (lit, 0, 0, 1), lit iff the lookup towards the
// light from one voxel back along V, leaving out the corners below half a voxel, is an exit (emulateGdm's
// rule, with the object-space light direction (in the surface's T, B, N frame) as L_t, the paper's choice, or
// with it mapped by the prism's
// inverse Jacobian: textureLight); refine on the signed distance volume traces the shadow on it instead
// (litByDistance); 2 prism id + 1, no GDM (the crack test of gdm_renderer.h); 3 shaded: (linear RGB, 1),
// shade() below, with that shadow.
//
// Not in the paper: refine on the signed distance volume (uTechnique 1 with uHasDistance), sphere tracing
// from T_in to T_out (traceDistance); see GdmTechnique::Refine.

in VertexData {
    vec3 worldPosition;
    vec3 texturePosition;
    flat uint prism;
    vec3 tangent;
    vec3 bitangent;
    vec3 normal;
} vIn;

layout(location = 0) out vec4 fragColor;
layout(depth_greater) out float gl_FragDepth;

// Per prism, 8 triangles x 3 corners x (world position, texture position): 48 vec4 (w unused).
layout(std430, binding = 0) readonly buffer PrismFaces { vec4 faces[]; };
layout(std430, binding = 1) readonly buffer GdmWeights { float weights[]; };
layout(std430, binding = 2) readonly buffer GdmEigen { float eigenMaps[]; };
layout(std430, binding = 3) readonly buffer GdmRaw { float rawValues[]; };
// The volumes, for shading: occupancy (1 inside) and linear albedo (RGB) per voxel, x fastest (§8).
layout(std430, binding = 4) readonly buffer GdmOccupancy { float occupancy[]; };
layout(std430, binding = 5) readonly buffer GdmAlbedo { float albedo[]; };
// The signed distance volume (tile widths, negative inside, x fastest), for refine and the normals.
layout(std430, binding = 6) readonly buffer GdmDistance { float distanceValues[]; };
// Per prism, the rows of the inverse of its Jacobian (isotropic texture frame -> world): 3 vec4 (w unused).
layout(std430, binding = 7) readonly buffer PrismLightFrames { vec4 lightFrames[]; };
// Environment lighting (GdmRenderer::setRtv, setEnvironment). The RTV: its basis (uRtvRank x 48, column
// k * 3 + c), its weights from uRtvWeightsAt (voxels x uRtvRank) and its inside flags from uRtvInsideAt (1
// where the voxel centre is inside the solid). Then per prism its 3 corners (tile u, v, mesh vertex, 0) and,
// from uLightingAt, per mesh vertex its meso-scale lighting (16 coefficients x RGB).
layout(std430, binding = 8) readonly buffer Rtv { float rtvData[]; };
layout(std430, binding = 9) readonly buffer EnvironmentLighting { float environmentData[]; };

uniform mat4 uViewProjection;
uniform vec3 uEye;
uniform vec3 uLight;
uniform vec3 uLightColor;  // the shaded output's Blinn-Phong terms, as the relief renderer's
uniform float uAmbient;
uniform float uSpecular;
uniform float uShininess;
uniform int uOutput;       // 0 uvw, 1 shadow, 2 the prism's id + 1 (the crack test), 3 shaded
uniform bool uHasAlbedo;
uniform int uTechnique;    // 0 gdm: the paper's lookup; 1 refine (see main); 2 march
uniform bool uHasDistance; // the signed distance volume is bound: refine traces it, normals are its gradient
uniform bool uJacobianLight; // the light direction in texture space: the prism's inverse Jacobian of the world one
uniform ivec3 uVoxels;     // Nx, Ny, Nz
uniform ivec3 uDistanceVoxels; // the signed distance volume's grid (the GDM's, or finer)
uniform ivec2 uDirections; // Ntheta, Nphi
uniform float uHeight;     // H
uniform int uRank;         // k; 0: the raw GDM
uniform float uTolerance;  // the exit rule's, tile widths along the ray
uniform bool uBilinearDirections;
uniform bool uEnvironment;  // shade with the RTV and the per-vertex lighting instead of the ambient term
uniform int uRtvRank;
uniform int uRtvWeightsAt;
uniform int uRtvInsideAt;
uniform int uLightingAt;
// The glossy RTV's SVD in the Rtv buffer (GdmRenderer::setGlossyRtv): rank (0: none), where W and E start,
// the view grid and the specular coefficient.
uniform int uGlossyRank;
uniform int uGlossyWeightsAt;
uniform int uGlossyBasisAt;
uniform ivec3 uGlossyViews;  // Ntheta, the view rows (Ntheta / 2), Nphi
uniform float uGlossySpecular;

const float kShadowBackoffVoxels = 1.0;
const float kShadowDropVoxels = 0.5;
// Refine on the signed distance volume: each step is this fraction of the distance there (the trilinear
// distance is within interpolation error of the true one, which is a safe step), and at least kMinStepVoxels;
// after kMaxSteps steps the GDM lookup answers for the rest of the segment. The crossing found is polished
// by kPolishSteps steps of regula falsi.
const float kStepFraction = 0.9;
const float kMinStepVoxels = 0.1;
const int kMaxSteps = 96;
const int kPolishSteps = 6;

#include "shared/gdm_lookup.h"

GdmLookupParams gdmParams() {
    return GdmLookupParams(uVoxels, uDirections, uHeight, uTolerance, uBilinearDirections);
}

// The shared lookup's fetch: the substituted value at voxel (i, j, k), direction (t, s).
float gdmValue(int i, int j, int k, int t, int s) {
    if (uRank == 0) {
        int index = (((k * uVoxels.y + j) * uVoxels.x + i) * uDirections.x + t) * uDirections.y + s;
        float value = rawValues[index];
        return isinf(value) ? gdmBoundaryDistance(gdmParams(), k, t) : value;
    }
    int row = s + uDirections.y * (i + uVoxels.x * j);
    int col = t + uDirections.x * k;
    int cols = uDirections.x * uVoxels.z;
    float sum = 0.0;
    for (int r = 0; r < uRank; ++r) sum += weights[row * uRank + r] * eigenMaps[r * cols + col];
    return sum;
}

// d(point, direction): x = distance, y = 1 for an exit (dmax); shared/gdm_lookup.h.
vec2 lookupGdm(vec3 point, vec3 direction, float dropBelow) {
    return gdmLookup(gdmParams(), point, direction, dropBelow);
}

int voxelIndex(int i, int j, int k) {
    i = gdmWrap(i, uVoxels.x);
    j = gdmWrap(j, uVoxels.y);
    k = clamp(k, 0, uVoxels.z - 1);
    return (k * uVoxels.y + j) * uVoxels.x + i;
}

// The 8 voxels and weights of the trilinear stencil at a texture point in a grid of `size` voxels (between
// voxel centres, wrapping in u, v, clamped in w).
void trilinearStencil(vec3 point, ivec3 size, out int index[8], out float weight[8]) {
    float fx = point.x * float(size.x) - 0.5;
    float fy = point.y * float(size.y) - 0.5;
    float fz = clamp(point.z / uHeight * float(size.z) - 0.5, 0.0, float(size.z - 1));
    vec3 base = floor(vec3(fx, fy, fz));
    vec3 a = vec3(fx, fy, fz) - base;
    for (int corner = 0; corner < 8; ++corner) {
        int dx = corner & 1, dy = (corner >> 1) & 1, dz = corner >> 2;
        weight[corner] = (dx == 1 ? a.x : 1.0 - a.x) * (dy == 1 ? a.y : 1.0 - a.y) * (dz == 1 ? a.z : 1.0 - a.z);
        int i = gdmWrap(int(base.x) + dx, size.x);
        int j = gdmWrap(int(base.y) + dy, size.y);
        int k = min(int(base.z) + dz, size.z - 1);
        index[corner] = (k * size.y + j) * size.x + i;
    }
}

// The occupancy volume, trilinear.
float occupancyAt(vec3 point) {
    int index[8];
    float weight[8];
    trilinearStencil(point, uVoxels, index, weight);
    float sum = 0.0;
    for (int corner = 0; corner < 8; ++corner) sum += weight[corner] * occupancy[index[corner]];
    return sum;
}

// The signed distance volume (tile widths, negative inside), trilinear.
float distanceAt(vec3 point) {
    int index[8];
    float weight[8];
    trilinearStencil(point, uDistanceVoxels, index, weight);
    float sum = 0.0;
    for (int corner = 0; corner < 8; ++corner) sum += weight[corner] * distanceValues[index[corner]];
    return sum;
}

// The outward normal in the isotropic frame at a texture point: the signed distance's gradient (with it) or
// minus the occupancy's (central differences one voxel apart); (0, 0, 0) where the gradient vanishes.
vec3 volumeNormal(vec3 p) {
    vec3 h = vec3(1.0 / float(uVoxels.x), 1.0 / float(uVoxels.y), uHeight / float(uVoxels.z));
    vec3 dx = vec3(h.x, 0.0, 0.0), dy = vec3(0.0, h.y, 0.0), dz = vec3(0.0, 0.0, h.z);
    vec3 gradient;
    if (uHasDistance)
        gradient = vec3(distanceAt(p + dx) - distanceAt(p - dx), distanceAt(p + dy) - distanceAt(p - dy),
                        distanceAt(p + dz) - distanceAt(p - dz)) / (2.0 * h);
    else
        gradient = -vec3(occupancyAt(p + dx) - occupancyAt(p - dx), occupancyAt(p + dy) - occupancyAt(p - dy),
                         occupancyAt(p + dz) - occupancyAt(p - dz));
    return length(gradient) > 1e-6 ? normalize(gradient) : vec3(0.0);
}

// The meso-scale lighting at a hit at texture point p (Wang et al. 2004, Sec. 4.2): the hit's prism's
// corners' per-vertex lighting, barycentric at the hit's (u, v) in the prism's footprint (clamped to it: a
// hit a rounding error outside).
void mesoLighting(vec3 p, out vec3 lighting[16]) {
    int corner = int(vIn.prism) * 12;
    vec2 t0 = vec2(environmentData[corner], environmentData[corner + 1]);
    vec2 t1 = vec2(environmentData[corner + 4], environmentData[corner + 5]);
    vec2 t2 = vec2(environmentData[corner + 8], environmentData[corner + 9]);
    vec2 e1 = t1 - t0, e2 = t2 - t0, q = p.xy - t0;
    float det = e1.x * e2.y - e2.x * e1.y;
    vec3 b = vec3(1.0, 0.0, 0.0);
    if (abs(det) > 1e-20) {
        float b1 = (q.x * e2.y - e2.x * q.y) / det, b2 = (e1.x * q.y - q.x * e1.y) / det;
        b = max(vec3(1.0 - b1 - b2, b1, b2), vec3(0.0));
        b /= max(b.x + b.y + b.z, 1e-20);
    }
    int v0 = uLightingAt + 48 * int(environmentData[corner + 2]);
    int v1 = uLightingAt + 48 * int(environmentData[corner + 6]);
    int v2 = uLightingAt + 48 * int(environmentData[corner + 10]);
    for (int k = 0; k < 16; ++k)
        lighting[k] = b.x * vec3(environmentData[v0 + 3 * k], environmentData[v0 + 3 * k + 1], environmentData[v0 + 3 * k + 2]) +
                      b.y * vec3(environmentData[v1 + 3 * k], environmentData[v1 + 3 * k + 1], environmentData[v1 + 3 * k + 2]) +
                      b.z * vec3(environmentData[v2 + 3 * k], environmentData[v2 + 3 * k + 1], environmentData[v2 + 3 * k + 2]);
}

// The RTV's voxel stencil at p (gdmRtvTransferAt's: trilinear over the voxel centres, wrapping in u, v and
// clamped in w, the corners inside the solid left out and the others' weights renormalised; all 8 inside:
// the nearest outside voxel centre of the 4 x 4 x 4 around the cell). Returns the number of voxels (0:
// none outside).
int rtvStencil(vec3 p, out int voxel[8], out float weight[8]) {
    float fx = p.x * float(uVoxels.x) - 0.5, fy = p.y * float(uVoxels.y) - 0.5;
    float fz = clamp(p.z / uHeight * float(uVoxels.z) - 0.5, 0.0, float(uVoxels.z - 1));
    vec3 cell = floor(vec3(fx, fy, fz));
    vec3 a = vec3(fx, fy, fz) - cell;
    int count = 0;
    float total = 0.0;
    for (int c = 0; c < 8; ++c) {
        int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
        float w = (dx == 1 ? a.x : 1.0 - a.x) * (dy == 1 ? a.y : 1.0 - a.y) * (dz == 1 ? a.z : 1.0 - a.z);
        if (w <= 0.0) continue;
        int index = voxelIndex(int(cell.x) + dx, int(cell.y) + dy, min(int(cell.z) + dz, uVoxels.z - 1));
        if (rtvData[uRtvInsideAt + index] > 0.5) continue;
        voxel[count] = index;
        weight[count] = w;
        total += w;
        ++count;
    }
    if (count == 0) {
        float best = 1e30;
        for (int dk = -1; dk <= 2; ++dk)
            for (int dj = -1; dj <= 2; ++dj)
                for (int di = -1; di <= 2; ++di) {
                    int k = int(cell.z) + dk;
                    if (k < 0 || k >= uVoxels.z) continue;
                    int index = voxelIndex(int(cell.x) + di, int(cell.y) + dj, k);
                    if (rtvData[uRtvInsideAt + index] > 0.5) continue;
                    vec3 offset = vec3((float(di) - a.x) / float(uVoxels.x), (float(dj) - a.y) / float(uVoxels.y),
                                       (float(dk) - a.z) * uHeight / float(uVoxels.z));
                    float length2 = dot(offset, offset);
                    if (length2 < best) {
                        best = length2;
                        voxel[0] = index;
                        weight[0] = 1.0;
                        count = 1;
                        total = 1.0;
                    }
                }
    }
    for (int c = 0; c < count; ++c) weight[c] /= total;
    return count;
}

// The diffuse environment term at a hit, for albedo 1 (gdmRtvRadiance's): the RTV's transfer dotted with the
// meso-scale lighting, per channel. The transfer is linear in the SVD's weights, so the weights are
// interpolated first and the basis applied once.
vec3 diffuseEnvironment(int voxel[8], float weight[8], int count, vec3 lighting[16]) {
    vec3 radiance = vec3(0.0);
    for (int r = 0; r < uRtvRank; ++r) {
        float w = 0.0;
        for (int c = 0; c < count; ++c) w += weight[c] * rtvData[uRtvWeightsAt + voxel[c] * uRtvRank + r];
        if (w == 0.0) continue;
        vec3 dotted = vec3(0.0);
        int row = r * 48;
        for (int k = 0; k < 16; ++k)
            dotted += vec3(rtvData[row + 3 * k], rtvData[row + 3 * k + 1], rtvData[row + 3 * k + 2]) * lighting[k];
        radiance += w * dotted;
    }
    return radiance;
}

// The glossy term at a hit seen from direction `view` (towards the eye, texture frame), without the specular
// coefficient (gdmGlossyTransferAt's lookup on the SVD): per coefficient k, G_k = sum over r of the
// stencil's W_k weights times the view's E_k value, bilinear between the view centres (phi wrapping, theta
// clamped to the first and last rows), then sum over k of G_k L_k.
vec3 glossyEnvironment(int voxel[8], float weight[8], int count, vec3 lighting[16], vec3 view) {
    const float pi = 3.14159265358979;
    vec3 w = normalize(view);
    float theta = acos(clamp(w.z, -1.0, 1.0));
    float phi = atan(w.y, w.x);
    if (phi < 0.0) phi += 2.0 * pi;
    int rows = uGlossyViews.y, columns = uGlossyViews.z;
    float ft = clamp(theta / pi * float(uGlossyViews.x) - 0.5, 0.0, float(rows - 1));
    float fp = phi / (2.0 * pi) * float(columns) - 0.5;
    float t0 = floor(ft), p0 = floor(fp);
    float at = ft - t0, ap = fp - p0;
    int views[4];
    float viewWeight[4];
    for (int c = 0; c < 4; ++c) {
        int dt = c & 1, dp = (c >> 1) & 1;
        views[c] = min(int(t0) + dt, rows - 1) * columns + gdmWrap(int(p0) + dp, columns);
        viewWeight[c] = (dt == 1 ? at : 1.0 - at) * (dp == 1 ? ap : 1.0 - ap);
    }
    int voxels = uVoxels.x * uVoxels.y * uVoxels.z, viewCount = rows * columns;
    vec3 radiance = vec3(0.0);
    for (int k = 0; k < 16; ++k) {
        float g = 0.0;
        for (int r = 0; r < uGlossyRank; ++r) {
            float wr = 0.0;
            for (int c = 0; c < count; ++c) wr += weight[c] * rtvData[uGlossyWeightsAt + (k * voxels + voxel[c]) * uGlossyRank + r];
            float er = 0.0;
            int basis = uGlossyBasisAt + (k * uGlossyRank + r) * viewCount;
            for (int c = 0; c < 4; ++c) er += viewWeight[c] * rtvData[basis + views[c]];
            g += wr * er;
        }
        radiance += g * lighting[k];
    }
    return radiance;
}

// The environment's light leaving a hit at texture point p of albedo `colour`, seen from `view`: the
// diffuse term times the albedo, plus the glossy term times its specular coefficient when there is one.
vec3 environmentTerm(vec3 p, vec3 colour, vec3 view) {
    vec3 lighting[16];
    mesoLighting(p, lighting);
    int voxel[8];
    float weight[8];
    int count = rtvStencil(p, voxel, weight);
    if (count == 0) return vec3(0.0);
    vec3 radiance = colour * diffuseEnvironment(voxel, weight, count, lighting);
    if (uGlossyRank > 0) radiance += uGlossySpecular * glossyEnvironment(voxel, weight, count, lighting, view);
    return radiance;
}

// Shading of a hit at texture point T (world P), the ray's texture direction V: the normal is volumeNormal's,
// taken to world by the mesh's interpolated tangent frame; the albedo is trilinear between the voxel
// centres; Blinn-Phong with the local shadow, plus the ambient term or, with an environment,
// environmentTerm.
vec3 shade(vec3 texturePoint, vec3 worldPoint, vec3 direction, bool lit) {
    vec3 n = volumeNormal(texturePoint);
    // Where the gradient vanishes (a hit on the shell's cut face), the face faces the ray.
    if (n == vec3(0.0)) n = -direction;
    vec3 world = normalize(n.x * vIn.tangent + n.y * vIn.bitangent + n.z * vIn.normal);
    vec3 toEye = normalize(uEye - worldPoint);
    if (dot(world, toEye) < 0.0) world = -world;  // a gradient estimated across a thin part
    vec3 toLight = normalize(uLight - worldPoint);
    vec3 colour = vec3(0.7);
    if (uHasAlbedo) {
        int index[8];
        float weight[8];
        trilinearStencil(texturePoint, uVoxels, index, weight);
        colour = vec3(0.0);
        for (int c = 0; c < 8; ++c) colour += weight[c] * vec3(albedo[3 * index[c]], albedo[3 * index[c] + 1], albedo[3 * index[c] + 2]);
    }
    // Blinn-Phong as the relief renderer's (shaders/relief/relief.frag.glsl).
    float diffuse = max(dot(world, toLight), 0.0);
    float specular = diffuse > 0.0 ? uSpecular * pow(max(dot(world, normalize(toLight + toEye)), 0.0), uShininess) : 0.0;
    // The environment (bi-scale radiance transfer) replaces the ambient term.
    vec3 result = uEnvironment ? environmentTerm(texturePoint, colour, -direction) : uAmbient * colour;
    if (lit) result += uLightColor * (diffuse * colour + specular);
    return result;
}

// The first point along the segment T_in + s V, 0 <= s < dt, where the occupancy volume reaches 0.5,
// sampled every `step` from `from` to `to`, the crossing placed by linear interpolation between the last
// sample below and the first at or above: x = distance, y = 1 if there is none.
vec2 marchOccupancy(vec3 start, vec3 direction, float from, float to, float step) {
    float previousAt = from;
    float previous = occupancyAt(start + from * direction);
    if (previous >= 0.5) return vec2(from, 0.0);
    while (previousAt < to) {
        float at = min(previousAt + step, to);
        float value = occupancyAt(start + at * direction);
        if (value >= 0.5) return vec2(mix(previousAt, at, (0.5 - previous) / max(value - previous, 1e-6)), 0.0);
        previousAt = at;
        previous = value;
    }
    return vec2(1e30, 1.0);
}

// The first zero of the trilinear signed distance along T_in + s V, 0 <= s < to, by sphere tracing (steps
// of kStepFraction times the distance, at least `minStep`) and regula falsi between the last point outside
// and the first inside: x = distance, y = 1 if there is none, z = 1 if kMaxSteps ran out first (x is then
// how far it came).
vec3 traceDistance(vec3 start, vec3 direction, float to, float minStep) {
    float s = 0.0;
    float f = distanceAt(start);
    if (f <= 0.0) return vec3(0.0, 0.0, 0.0);
    for (int n = 0; n < kMaxSteps; ++n) {
        if (s >= to) return vec3(1e30, 1.0, 0.0);
        float next = min(s + max(kStepFraction * f, minStep), to);
        float g = distanceAt(start + next * direction);
        if (g <= 0.0) {
            float a = s, fa = f, b = next, fb = g;
            for (int m = 0; m < kPolishSteps; ++m) {
                // Kept off the ends, so that one end that barely moves still shrinks the bracket.
                float c = clamp(a + (b - a) * fa / (fa - fb), mix(a, b, 0.05), mix(a, b, 0.95));
                float fc = distanceAt(start + c * direction);
                if (fc > 0.0) {
                    a = c;
                    fa = fc;
                } else {
                    b = c;
                    fb = fc;
                }
            }
            return vec3(a + (b - a) * fa / (fa - fb), 0.0, 0.0);
        }
        s = next;
        f = g;
    }
    return vec3(s, 1.0, 1.0);
}

// The direction to the light in the isotropic texture frame: the world one in the surface's frame (the
// paper's), or mapped by the
// prism's inverse Jacobian.
vec3 textureLight(vec3 worldPoint) {
    vec3 toLight = uLight - worldPoint;
    if (uJacobianLight) {
        int row = int(vIn.prism) * 3;
        // A degenerate prism's rows are zero: it keeps the tangent frame below.
        if (lightFrames[row].xyz != vec3(0.0))
            return normalize(vec3(dot(lightFrames[row].xyz, toLight), dot(lightFrames[row + 1].xyz, toLight),
                                  dot(lightFrames[row + 2].xyz, toLight)));
    }
    // The paper's "object space light direction": the direction in the surface's own frame at the hit, T, B
    // and N interpolated from the mesh (on the flat quad, world x, y, z).
    vec3 n = normalize(vIn.normal);
    vec3 t = normalize(vIn.tangent - dot(vIn.tangent, n) * n);
    vec3 b = normalize(vIn.bitangent - dot(vIn.bitangent, n) * n - dot(vIn.bitangent, t) * t);
    return normalize(vec3(dot(toLight, t), dot(toLight, b), dot(toLight, n)));
}

// Refine's shadow on the signed distance: lit iff the normal (volumeNormal) faces the light and sphere
// tracing from kShadowOffsetVoxels off the surface along it towards the light meets no zero crossing before
// it leaves the slab 0 <= w <= 1 (CONVENTIONS §8's local shadow); where the steps run out, the GDM lookup
// from there answers.
const float kShadowOffsetVoxels = 0.25;
bool litByDistance(vec3 point, vec3 toLight, float voxel) {
    vec3 n = volumeNormal(point);
    if (n != vec3(0.0) && dot(n, toLight) <= 0.0) return false;
    vec3 start = point + kShadowOffsetVoxels * voxel * n;
    float to = toLight.z > 1e-6 ? (uHeight - start.z) / toLight.z
             : toLight.z < -1e-6 ? -start.z / toLight.z : 64.0;
    to = clamp(to, 0.0, 64.0);
    vec3 traced = traceDistance(start, toLight, to, kMinStepVoxels * voxel);
    if (traced.z > 0.5) return lookupGdm(start + traced.x * toLight, toLight, kShadowDropVoxels * voxel).y > 0.5;
    return traced.y > 0.5;
}

void main() {
    if (uOutput == 2) {
        fragColor = vec4(float(vIn.prism + 1u), 0.0, 0.0, 1.0);
        gl_FragDepth = gl_FragCoord.z;
        return;
    }
    vec3 origin = vIn.worldPosition;
    vec3 ray = normalize(origin - uEye);
    // The exit: the nearest of the prism's faces past the entry.
    float tExit = 1e30;
    vec3 textureExit = vIn.texturePosition;
    int base = int(vIn.prism) * 48;
    for (int f = 0; f < 8; ++f) {
        vec3 p0 = faces[base + 6 * f + 0].xyz, p1 = faces[base + 6 * f + 2].xyz, p2 = faces[base + 6 * f + 4].xyz;
        // Moeller-Trumbore.
        vec3 e1 = p1 - p0, e2 = p2 - p0;
        // Only a face the ray leaves the prism through can be its exit: the top and the fins are wound
        // outward from the prism, the base (face 0) along +N, into it. Without this test a face that shares
        // an edge with the entry face, met within the edge tolerance a hair past the entry, ends the
        // segment at once, and the prism shows nothing along its edges (rays then hit deeper prisms).
        float leaving = dot(ray, cross(e1, e2));
        if ((f == 0 ? -leaving : leaving) <= 0.0) continue;
        vec3 q = cross(ray, e2);
        float det = dot(e1, q);
        if (abs(det) < 1e-12) continue;
        vec3 s = origin - p0;
        float beta = dot(s, q) / det;
        vec3 r = cross(s, e1);
        float gamma = dot(ray, r) / det;
        float t = dot(e2, r) / det;
        const float edge = -1e-5;
        if (beta < edge || gamma < edge || beta + gamma > 1.0 - edge) continue;
        if (t <= 1e-6 || t >= tExit) continue;
        tExit = t;
        textureExit = (1.0 - beta - gamma) * faces[base + 6 * f + 1].xyz + beta * faces[base + 6 * f + 3].xyz +
                      gamma * faces[base + 6 * f + 5].xyz;
    }
    if (tExit >= 1e30) discard;
    vec3 segment = textureExit - vIn.texturePosition;
    float dt = length(segment);
    if (dt <= 0.0) discard;
    vec3 direction = segment / dt;
    float voxel = uHeight / float(uVoxels.z);
    vec2 hit;
    if (uTechnique == 2) {
        // march: the occupancy every voxel from T_in to T_out, no GDM (the paper's slice-based comparison).
        hit = marchOccupancy(vIn.texturePosition, direction, 0.0, dt, voxel);
    } else if (uTechnique == 1 && uHasDistance) {
        // refine on the signed distance: sphere tracing from T_in to T_out, so that the lookup's misses and
        // its hits in the wrong place are both corrected; where the steps run out (a ray grazing a surface
        // for long), the GDM lookup from there answers for the rest.
        vec3 traced = traceDistance(vIn.texturePosition, direction, dt, kMinStepVoxels * voxel);
        hit = traced.xy;
        if (traced.z > 0.5) {
            vec2 rest = lookupGdm(vIn.texturePosition + traced.x * direction, direction, -1.0);
            hit = vec2(traced.x + rest.x, rest.y);
        }
    } else {
        hit = lookupGdm(vIn.texturePosition, direction, -1.0);
        if (uTechnique == 1 && hit.y < 0.5 && hit.x < dt) {
            // refine without a distance volume: the occupancy's crossing within two voxels of the GDM's
            // answer, a quarter voxel apart.
            vec2 near = marchOccupancy(vIn.texturePosition, direction, max(hit.x - 2.0 * voxel, 0.0),
                                       min(hit.x + 2.0 * voxel, dt), 0.25 * voxel);
            if (near.y < 0.5) hit = near;
        }
    }
    if (hit.y > 0.5 || hit.x >= dt) discard;
    vec3 texturePoint = vIn.texturePosition + hit.x * direction;
    vec3 worldPoint = origin + (hit.x / dt) * tExit * ray;
    vec4 clip = uViewProjection * vec4(worldPoint, 1.0);
    gl_FragDepth = (gl_DepthRange.diff * (clip.z / clip.w) + gl_DepthRange.near + gl_DepthRange.far) * 0.5;
    if (uOutput == 0) {
        fragColor = vec4(fract(texturePoint.x), fract(texturePoint.y), clamp(texturePoint.z / uHeight, 0.0, 1.0), 1.0);
    } else {
        vec3 back = texturePoint - kShadowBackoffVoxels * voxel * direction;
        vec3 toLight = textureLight(worldPoint);
        vec2 shadow = uTechnique == 1 && uHasDistance ? vec2(0.0, litByDistance(texturePoint, toLight, voxel) ? 1.0 : 0.0)
                                                      : lookupGdm(back, toLight, kShadowDropVoxels * voxel);
        if (uOutput == 1)
            fragColor = vec4(shadow.y, 0.0, 0.0, 1.0);
        else
            fragColor = vec4(shade(texturePoint, worldPoint, direction, shadow.y > 0.5), 1.0);
    }
}
