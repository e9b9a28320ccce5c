#include "strata/gdm/gdm_mesh_reference.h"

#include "strata/core/error.h"
#include "strata/core/parallel.h"

#include "mesh_reference_scene.h"
#include "periodic_scene.h"
#include "scene_images.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace strata {
namespace {

using namespace detail;

// The inside test at a boundary point is made this far inside the prism (tile widths), as
// renderGdmReference's at the box's entry point.
constexpr double kEntryNudge = 1e-7;
// The shadow ray starts this many tile lengths (T / H, world units) off the surface: renderGdmReference's
// 1e-5 tile widths.
constexpr double kShadowOffsetTiles = 1e-5;
// A ray crosses the shell's boundary a few times at most (in, through the base, out and back in on a closed
// mesh); this only stops a ray that float rounding keeps on one face.
constexpr int kMaxCrossings = 256;
// Edges shorter than this (tile widths, in texture space) are not split, whatever their curvature: ends
// the subdivision on any input.
constexpr double kMinSplitLength = 1e-5;

using FaceKind = WarpedFaceKind;

double cross2(const glm::dvec2& a, const glm::dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

// One prism's map from texture space (u, v, z) to world: X = sum_i b_i (P_i + (z / H) T N_i).
struct PrismMap {
    std::array<glm::dvec2, 3> t;
    std::array<glm::dvec3, 3> base;
    std::array<glm::dvec3, 3> normal;
    std::array<glm::dvec2, 3> gradient;  // of b_i in (u, v)
    double det = 0.0;                    // 2 x the footprint's signed area
    double thickness = 0.0;              // T
    double height = 0.0;                 // H

    // b_i(q) = cross(t_k - t_j, q - t_j) / det, (i, j, k) cyclic: each exactly 0 on its own edge's line.
    double barycentric(int i, const glm::dvec2& q) const {
        const glm::dvec2& tj = t[std::size_t((i + 1) % 3)];
        const glm::dvec2& tk = t[std::size_t((i + 2) % 3)];
        return cross2(tk - tj, q - tj) / det;
    }

    glm::dvec3 world(const glm::dvec3& p) const {
        const glm::dvec2 q(p.x, p.y);
        const double lift = p.z / height * thickness;
        glm::dvec3 x(0.0);
        for (int i = 0; i < 3; ++i) {
            const auto n = std::size_t(i);
            x += barycentric(i, q) * (base[n] + lift * normal[n]);
        }
        return x;
    }

    // dX / d(u, v, z) at p, as columns.
    glm::dmat3 jacobian(const glm::dvec3& p) const {
        const glm::dvec2 q(p.x, p.y);
        const double lift = p.z / height * thickness;
        glm::dvec3 du(0.0), dv(0.0), dz(0.0);
        for (int i = 0; i < 3; ++i) {
            const auto n = std::size_t(i);
            const glm::dvec3 corner = base[n] + lift * normal[n];
            du += gradient[n].x * corner;
            dv += gradient[n].y * corner;
            dz += barycentric(i, q) * (thickness / height) * normal[n];
        }
        return glm::dmat3(du, dv, dz);
    }

    // |Q(e)| / 6 for the edge a -> b (the header's bound on a triangle's chord error): exactly the same
    // number for b -> a (negating a difference is exact).
    double chordBound(const glm::dvec3& a, const glm::dvec3& b) const {
        const glm::dvec3 e = b - a;
        glm::dvec3 turn(0.0);
        for (std::size_t i = 0; i < 3; ++i) turn += glm::dot(gradient[i], glm::dvec2(e.x, e.y)) * normal[i];
        return std::abs(e.z) / height * thickness * glm::length(turn) / 3.0;
    }
};

// Splits the triangle at the midpoints of the edges whose chord bound exceeds `tolerance` (each edge's own
// decision: see the header), recursively, and emits the flat pieces.
template <class Emit>
void subdivide(const PrismMap& map, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
               double tolerance, int depth, const Emit& emit) {
    const auto split = [&](const glm::dvec3& p, const glm::dvec3& q) {
        const glm::dvec3 e = q - p;
        return depth < 24 && glm::length(e) > kMinSplitLength && map.chordBound(p, q) > tolerance;
    };
    const bool ab = split(a, b), bc = split(b, c), ca = split(c, a);
    const int count = int(ab) + int(bc) + int(ca);
    if (count == 0) {
        emit(a, b, c);
        return;
    }
    const auto mid = [](const glm::dvec3& p, const glm::dvec3& q) { return (p + q) * 0.5; };
    const int next = depth + 1;
    if (count == 3) {
        const glm::dvec3 mab = mid(a, b), mbc = mid(b, c), mca = mid(c, a);
        subdivide(map, a, mab, mca, tolerance, next, emit);
        subdivide(map, mab, b, mbc, tolerance, next, emit);
        subdivide(map, mca, mbc, c, tolerance, next, emit);
        subdivide(map, mab, mbc, mca, tolerance, next, emit);
        return;
    }
    if (count == 1) {
        // Rotate so that the split edge is a -> b.
        if (bc) return subdivide(map, b, c, a, tolerance, depth, emit);
        if (ca) return subdivide(map, c, a, b, tolerance, depth, emit);
        const glm::dvec3 mab = mid(a, b);
        subdivide(map, a, mab, c, tolerance, next, emit);
        subdivide(map, mab, b, c, tolerance, next, emit);
        return;
    }
    // Two: rotate so that a -> b and b -> c are split, c -> a is not.
    if (!ab) return subdivide(map, b, c, a, tolerance, depth, emit);
    if (!bc) return subdivide(map, c, a, b, tolerance, depth, emit);
    const glm::dvec3 mab = mid(a, b), mbc = mid(b, c);
    subdivide(map, mab, b, mbc, tolerance, next, emit);
    subdivide(map, a, mab, c, tolerance, next, emit);
    subdivide(map, mab, mbc, c, tolerance, next, emit);
}

// Where the segment p -> q crosses the plane f = 0 (f affine, fp and fq its values at the ends, of
// opposite signs), computed from the lexicographically smaller end: a shared edge's crossing is the same
// point in both triangles that have it.
glm::dvec3 crossing(const glm::dvec3& p, double fp, const glm::dvec3& q, double fq) {
    const bool swap = q.x < p.x || (q.x == p.x && (q.y < p.y || (q.y == p.y && q.z < p.z)));
    if (swap) return crossing(q, fq, p, fp);
    return p + (fp / (fp - fq)) * (q - p);
}

// The prism's texture volume as 5 half-spaces f >= 0: b_0, b_1, b_2, z, H - z.
double planeValue(const PrismMap& map, int plane, const glm::dvec3& p) {
    if (plane < 3) return map.barycentric(plane, glm::dvec2(p.x, p.y));
    if (plane == 3) return p.z;
    return map.height - p.z;
}

// Clips a convex polygon (texture space) to the prism's volume (Sutherland-Hodgman).
void clipToPrism(const PrismMap& map, std::vector<glm::dvec3>& polygon, std::vector<glm::dvec3>& scratch) {
    for (int plane = 0; plane < 5 && polygon.size() >= 3; ++plane) {
        scratch.clear();
        const std::size_t n = polygon.size();
        for (std::size_t k = 0; k < n; ++k) {
            const glm::dvec3& p = polygon[k];
            const glm::dvec3& q = polygon[(k + 1) % n];
            const double fp = planeValue(map, plane, p);
            const double fq = planeValue(map, plane, q);
            if (fp >= 0.0) scratch.push_back(p);
            if ((fp >= 0.0) != (fq >= 0.0)) scratch.push_back(crossing(p, fp, q, fq));
        }
        std::swap(polygon, scratch);
    }
}

// A clipped face that lies in one of the prism's bounding planes with the solid it bounds outside the prism
// (its outward normal points into the prism): the face of a neighbouring translate whose solid the plane
// cuts away, kept by the clip only because it lies on the plane. The neighbouring prism has it; here it
// would make a ray that leaves the prism through the solid's section hit the plane.
bool facesOutOfPrism(const PrismMap& map, const std::vector<glm::dvec3>& polygon, const glm::dvec3& normal) {
    // Tile widths: the rounding of a clip point's plane value, far below any feature.
    constexpr double kOnPlane = 1e-9;
    for (int plane = 0; plane < 5; ++plane) {
        bool on = true;
        for (const glm::dvec3& p : polygon) on = on && std::abs(planeValue(map, plane, p)) <= kOnPlane;
        if (!on) continue;
        const glm::dvec3 inward = plane < 3 ? glm::dvec3(map.gradient[std::size_t(plane)], 0.0)
                                            : glm::dvec3(0.0, 0.0, plane == 3 ? 1.0 : -1.0);
        if (glm::dot(inward, normal) > 0.0) return true;
    }
    return false;
}

struct PrismGeometry {
    std::vector<glm::vec3> world;  // 3 per face
    std::vector<WarpedFace> faces;
    std::size_t clipped = 0;
    std::size_t solid = 0;
    std::size_t boundary = 0;
};

// Emits one flat piece: its world corners through the map, turned so that its winding gives the outward
// normal (the cofactor J^-T of the map at its centre takes the texture normal to the world one).
void emitFace(const PrismMap& map, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
              const glm::dvec3& textureNormal, FaceKind kind, PrismGeometry& out) {
    std::array<glm::dvec3, 3> tex = {a, b, c};
    std::array<glm::dvec3, 3> world = {map.world(a), map.world(b), map.world(c)};
    glm::dvec3 n = glm::cross(world[1] - world[0], world[2] - world[0]);
    const double length = glm::length(n);
    if (!(length > 0.0)) return;
    const glm::dmat3 jacobian = map.jacobian((a + b + c) / 3.0);
    const glm::dvec3 expected = glm::inverse(glm::transpose(jacobian)) * textureNormal;
    if (glm::dot(n, expected) < 0.0) {
        std::swap(tex[1], tex[2]);
        std::swap(world[1], world[2]);
        n = -n;
    }
    for (const glm::dvec3& w : world) out.world.emplace_back(w);
    out.faces.push_back({tex, glm::vec3(n / length), glm::vec3(textureNormal), kind, 0});
    (kind == FaceKind::Solid ? out.solid : out.boundary) += 1;
}

// The solid's triangles in texture space, and their bounds, once.
struct SolidTriangles {
    std::vector<std::array<glm::dvec3, 3>> corners;
    std::vector<glm::dvec3> normals;  // outward, unit (zero for a degenerate triangle)
    std::vector<glm::dvec2> lo, hi;   // (u, v) bounds
    glm::dvec3 min{0.0}, max{0.0};
};

SolidTriangles solidTriangles(const SolidMesh& solid) {
    SolidTriangles result;
    result.min = glm::dvec3(std::numeric_limits<double>::max());
    result.max = glm::dvec3(std::numeric_limits<double>::lowest());
    for (const auto& triangle : solid.triangles) {
        std::array<glm::dvec3, 3> c;
        for (std::size_t k = 0; k < 3; ++k) c[k] = glm::dvec3(solid.positions[triangle[k]]);
        const glm::dvec3 n = glm::cross(c[1] - c[0], c[2] - c[0]);
        const double length = glm::length(n);
        result.corners.push_back(c);
        result.normals.push_back(length > 0.0 ? n / length : glm::dvec3(0.0));
        const glm::dvec3 lo = glm::min(c[0], glm::min(c[1], c[2]));
        const glm::dvec3 hi = glm::max(c[0], glm::max(c[1], c[2]));
        result.lo.emplace_back(lo.x, lo.y);
        result.hi.emplace_back(hi.x, hi.y);
        result.min = glm::min(result.min, lo);
        result.max = glm::max(result.max, hi);
    }
    return result;
}

PrismGeometry buildPrism(const PrismMap& map, const SolidTriangles& solid, const std::array<bool, 3>& cutFins,
                         double tolerance) {
    PrismGeometry out;
    const double height = map.height;
    // Top and base: flat, exact.
    emitFace(map, glm::dvec3(map.t[0], height), glm::dvec3(map.t[1], height), glm::dvec3(map.t[2], height),
             glm::dvec3(0.0, 0.0, 1.0), FaceKind::Top, out);
    emitFace(map, glm::dvec3(map.t[0], 0.0), glm::dvec3(map.t[1], 0.0), glm::dvec3(map.t[2], 0.0),
             glm::dvec3(0.0, 0.0, -1.0), FaceKind::Base, out);
    // The fins that are faces (rims and seams): bilinear, subdivided.
    for (int e = 0; e < 3; ++e) {
        if (!cutFins[std::size_t(e)]) continue;
        const auto a = std::size_t(e), b = std::size_t((e + 1) % 3), opposite = std::size_t((e + 2) % 3);
        const glm::dvec2 outward = -glm::normalize(map.gradient[opposite]);
        const glm::dvec3 normal(outward, 0.0);
        const glm::dvec3 a0(map.t[a], 0.0), b0(map.t[b], 0.0), b1(map.t[b], height), a1(map.t[a], height);
        const auto emit = [&](const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
            emitFace(map, p, q, r, normal, FaceKind::Fin, out);
        };
        subdivide(map, a0, b0, b1, tolerance, 0, emit);
        subdivide(map, a0, b1, a1, tolerance, 0, emit);
    }

    // The solid: every translate that reaches over the footprint.
    glm::dvec2 lo = glm::min(map.t[0], glm::min(map.t[1], map.t[2]));
    glm::dvec2 hi = glm::max(map.t[0], glm::max(map.t[1], map.t[2]));
    if (solid.corners.empty()) return out;
    const int iFirst = int(std::floor(lo.x - solid.max.x)), iLast = int(std::ceil(hi.x - solid.min.x));
    const int jFirst = int(std::floor(lo.y - solid.max.y)), jLast = int(std::ceil(hi.y - solid.min.y));
    std::vector<glm::dvec3> polygon, scratch;
    for (int j = jFirst; j <= jLast; ++j)
        for (int i = iFirst; i <= iLast; ++i) {
            const glm::dvec2 shift(i, j);
            for (std::size_t k = 0; k < solid.corners.size(); ++k) {
                const glm::dvec2 tLo = solid.lo[k] + shift, tHi = solid.hi[k] + shift;
                if (tHi.x < lo.x || tLo.x > hi.x || tHi.y < lo.y || tLo.y > hi.y) continue;
                if (solid.normals[k] == glm::dvec3(0.0)) continue;
                polygon.clear();
                for (const glm::dvec3& c : solid.corners[k]) polygon.push_back(c + glm::dvec3(shift, 0.0));
                clipToPrism(map, polygon, scratch);
                if (polygon.size() < 3 || facesOutOfPrism(map, polygon, solid.normals[k])) continue;
                const auto emit = [&](const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
                    emitFace(map, p, q, r, solid.normals[k], FaceKind::Solid, out);
                };
                for (std::size_t v = 1; v + 1 < polygon.size(); ++v) {
                    ++out.clipped;
                    subdivide(map, polygon[0], polygon[v], polygon[v + 1], tolerance, 0, emit);
                }
            }
        }
    return out;
}

// The faces a ray has already crossed, which Embree must not report again: the walk along a ray goes on
// from the last crossing's distance itself, so that a face that lies at (nearly) the same distance, such as
// the other prism's side of a seam, is met in its turn and not stepped over. An Embree context filter.
struct SkipContext {
    RTCIntersectContext context;  // first: Embree hands the filter a pointer to it
    std::array<unsigned, 32> skip{};
    int count = 0;
    int next = 0;  // the ring's oldest entry, once full

    void add(unsigned primitive) {
        skip[std::size_t(next)] = primitive;
        next = (next + 1) % int(skip.size());
        count = std::min(count + 1, int(skip.size()));
    }
};

void skipCrossed(const RTCFilterFunctionNArguments* args) {
    const auto* crossed = reinterpret_cast<const SkipContext*>(args->context);
    for (unsigned n = 0; n < args->N; ++n) {
        if (args->valid[n] == 0) continue;
        const unsigned primitive = RTCHitN_primID(args->hit, args->N, n);
        const auto end = crossed->skip.begin() + crossed->count;
        if (std::find(crossed->skip.begin(), end, primitive) != end) args->valid[n] = 0;
    }
}

}  // namespace

WarpedCrossing detail::firstWarpedHit(const WarpedScene& warped, const glm::dvec3& origin,
                                      const glm::dvec3& direction, double tFar, const WarpedRayRule& rule) {
    WarpedCrossing result;
    SkipContext crossed;
    rtcInitIntersectContext(&crossed.context);
    crossed.context.filter = skipCrossed;
    float tNear = 0.0f;
    for (int step = 0; step < kMaxCrossings; ++step) {
        RTCRayHit rayHit;
        setRay(rayHit, origin, glm::vec3(direction), tFar);
        rayHit.ray.tnear = tNear;
        rtcIntersect1(warped.scene.get(), &crossed.context, &rayHit);
        if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return result;
        const double t = double(rayHit.ray.tfar);
        const WarpedFace& face = warped.faces[rayHit.hit.primID];
        const glm::dvec3 normal(face.normal);
        const bool entering = glm::dot(normal, direction) < 0.0;
        const double u = double(rayHit.hit.u), v = double(rayHit.hit.v);
        const glm::dvec3 texture =
            (1.0 - u - v) * face.texture[0] + u * face.texture[1] + v * face.texture[2];
        bool hit = false;
        if (face.kind == FaceKind::Solid) {
            hit = entering || rule.anySolidFace;
            if (!entering) result.exitFace = true;
        } else if (face.kind == FaceKind::Base && rule.baseBlocks) {
            hit = true;
        } else if (entering) {
            if (face.kind == FaceKind::Base) {
                result.fromBelow = true;
                if (!rule.throughBase) return result;
            }
            glm::dvec3 inside = texture - kEntryNudge * glm::dvec3(face.textureNormal);
            inside.x -= std::floor(inside.x);
            inside.y -= std::floor(inside.y);
            hit = insideSolid(warped.periodic, inside);
        }
        if (hit) {
            result.found = true;
            result.t = t;
            result.texture = texture;
            result.normal = normal;
            result.kind = face.kind;
            result.prism = face.prism;
            return result;
        }
        crossed.add(rayHit.hit.primID);
        tNear = rayHit.ray.tfar;
    }
    return result;
}

WarpedScene detail::buildWarpedScene(const SolidMesh& solid, const Mesh& mesh, const PrismShellOptions& shell,
                                     double chordTolerance, const std::string& what, EmbreeErrors& errors,
                                     GdmMeshReferenceStats& stats) {
    PrismShellOptions shellOptions = shell;
    shellOptions.height = solid.height;
    const PrismShell prisms = buildPrismShell(mesh, shellOptions);
    const double H = solid.height;
    const double T = prisms.thickness;

    // Fins used by one prism only are the shell's boundary (prisms without a footprint are left out).
    std::size_t rimFins = 0, seamFins = 0;
    std::vector<PrismMap> maps(prisms.prisms.size());
    std::vector<bool> usable(prisms.prisms.size(), false);
    for (std::size_t p = 0; p < prisms.prisms.size(); ++p) {
        PrismMap& map = maps[p];
        map.thickness = T;
        map.height = H;
        for (std::size_t i = 0; i < 3; ++i) {
            const std::uint32_t s = prisms.prisms[p][i];
            const glm::vec2 uv = mesh.vertices[prisms.corners[p][i]].uv;
            map.t[i] = shellOptions.tiling * glm::dvec2(uv);
            map.base[i] = glm::dvec3(prisms.base[s]);
            map.normal[i] = glm::dvec3(prisms.normal[s]);
        }
        map.det = cross2(map.t[1] - map.t[0], map.t[2] - map.t[0]);
        const glm::dvec2 extent = glm::max(map.t[0], glm::max(map.t[1], map.t[2])) -
                                  glm::min(map.t[0], glm::min(map.t[1], map.t[2]));
        usable[p] = std::isfinite(map.det) && std::abs(map.det) > 1e-12 * extent.x * extent.y &&
                    std::abs(map.det) > 0.0;
        if (!usable[p]) continue;
        for (std::size_t i = 0; i < 3; ++i) {
            const glm::dvec2 edge = map.t[(i + 2) % 3] - map.t[(i + 1) % 3];
            map.gradient[i] = glm::dvec2(-edge.y, edge.x) / map.det;
        }
    }
    // The fins that are faces: those of one prism only (the shell's rim), and those between prisms whose
    // texture positions do not continue across them (a uv seam that does not fall on whole tiles, a mesh
    // whose uvs jump: the solid does not continue there, so a ray that crosses into the next prism may land
    // inside its solid, on a cut face). Either prism has its own side of a seam.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::pair<std::size_t, int>>> edgeUse;
    const auto shellVertex = [&](std::size_t p, int corner) {
        return prisms.prisms[p][std::size_t(corner % 3)];
    };
    for (std::size_t p = 0; p < prisms.prisms.size(); ++p)
        if (usable[p])
            for (int e = 0; e < 3; ++e) {
                const std::uint32_t a = shellVertex(p, e), b = shellVertex(p, e + 1);
                edgeUse[{std::min(a, b), std::max(a, b)}].emplace_back(p, e);
            }
    // The tile coordinates prism p gives shell vertex s (one of its corners).
    const auto tileOf = [&](std::size_t p, std::uint32_t s) {
        for (std::size_t i = 0; i < 3; ++i)
            if (prisms.prisms[p][i] == s) return maps[p].t[i];
        return glm::dvec2(0.0);
    };
    // Tile widths: uvs are floats, so positions that continue agree to float rounding of the tiling * uv.
    constexpr double kSeamTolerance = 1e-4;
    std::vector<std::array<bool, 3>> cutFins(prisms.prisms.size(), {false, false, false});
    for (const auto& [edge, users] : edgeUse) {
        bool cut = users.size() != 2;
        if (!cut) {
            const std::size_t p = users[0].first, q = users[1].first;
            const glm::dvec2 da = tileOf(q, edge.first) - tileOf(p, edge.first);
            const glm::dvec2 db = tileOf(q, edge.second) - tileOf(p, edge.second);
            const glm::dvec2 whole = glm::round(da);
            cut = glm::length(da - db) > kSeamTolerance || glm::length(da - whole) > kSeamTolerance;
            if (cut) ++seamFins;
        } else if (users.size() == 1) {
            ++rimFins;
        } else {
            seamFins += users.size();
        }
        if (cut)
            for (const auto& [p, e] : users) cutFins[p][std::size_t(e)] = true;
    }

    const SolidTriangles triangles = solidTriangles(solid);
    std::vector<PrismGeometry> pieces(prisms.prisms.size());
    parallelFor(std::size_t(0), prisms.prisms.size(), [&](std::size_t p) {
        if (!usable[p]) return;
        pieces[p] = buildPrism(maps[p], triangles, cutFins[p], chordTolerance * T);
    });

    GdmMeshReferenceStats& counts = stats;
    counts = {};
    counts.prisms = prisms.prisms.size();
    counts.rimFins = rimFins;
    counts.seamFins = seamFins;
    WarpedScene warped;
    warped.height = H;
    warped.thickness = T;
    warped.baseNormals.assign(prisms.prisms.size(), glm::dvec3(0.0));
    std::vector<glm::vec3> world;
    for (std::size_t p = 0; p < pieces.size(); ++p) {
        if (!usable[p]) ++counts.skippedPrisms;
        counts.clippedTriangles += pieces[p].clipped;
        counts.solidTriangles += pieces[p].solid;
        counts.boundaryTriangles += pieces[p].boundary;
        world.insert(world.end(), pieces[p].world.begin(), pieces[p].world.end());
        for (WarpedFace& face : pieces[p].faces) face.prism = std::uint32_t(p);
        warped.faces.insert(warped.faces.end(), pieces[p].faces.begin(), pieces[p].faces.end());
        pieces[p] = {};
        if (!usable[p]) continue;
        // The base triangle's normal, turned as emitFace turns the base's (into the shell: texture +z).
        const PrismMap& map = maps[p];
        const glm::dvec3 b0 = map.world(glm::dvec3(map.t[0], 0.0)), b1 = map.world(glm::dvec3(map.t[1], 0.0)),
                         b2 = map.world(glm::dvec3(map.t[2], 0.0));
        glm::dvec3 up = glm::cross(b1 - b0, b2 - b0);
        const glm::dvec2 centre = (map.t[0] + map.t[1] + map.t[2]) / 3.0;
        const glm::dvec3 expected =
            glm::inverse(glm::transpose(map.jacobian(glm::dvec3(centre, 0.0)))) * glm::dvec3(0.0, 0.0, 1.0);
        if (glm::dot(up, expected) < 0.0) up = -up;
        if (glm::length(up) > 0.0) warped.baseNormals[p] = glm::normalize(up);
    }

    warped.periodic = buildScene(solid, what, errors);
    RTCDevice device = warped.periodic.device.get();
    warped.scene.reset(rtcNewScene(device));
    if (!warped.scene) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    rtcSetSceneFlags(warped.scene.get(), RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(warped.scene.get(), RTC_BUILD_QUALITY_HIGH);
    GeometryHandle& geometry = warped.geometry;
    if (!warped.faces.empty()) {
        geometry.reset(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE));
        if (!geometry) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
        // Embree reads 16 bytes at the last vertex: one float of padding.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX,
                                                                     0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                                     world.size() + 1));
        auto* indices = static_cast<std::uint32_t*>(
            rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                    3 * sizeof(std::uint32_t), warped.faces.size()));
        if (!vertices || !indices) throw Error(ErrorKind::Runtime, what + ": " + errors.first);
        for (std::size_t v = 0; v < world.size(); ++v) {
            vertices[3 * v + 0] = world[v].x;
            vertices[3 * v + 1] = world[v].y;
            vertices[3 * v + 2] = world[v].z;
        }
        vertices[3 * world.size() + 0] = vertices[3 * world.size() + 1] = vertices[3 * world.size() + 2] =
            0.0f;
        for (std::size_t k = 0; k < 3 * warped.faces.size(); ++k) indices[k] = std::uint32_t(k);
        rtcCommitGeometry(geometry.get());
        rtcAttachGeometry(warped.scene.get(), geometry.get());
    }
    rtcCommitScene(warped.scene.get());
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE || !errors.first.empty())
        throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    return warped;
}

GdmSceneImages renderGdmMeshReference(const SolidMesh& solid, const Mesh& mesh,
                                      const PrismShellOptions& shell, const Camera& camera, glm::dvec3 light,
                                      int width, int height, const GdmMeshReferenceOptions& options,
                                      GdmMeshReferenceStats* stats) {
    const std::string what = "GDM mesh reference of " + solid.source;
    detail::checkGdmSceneInput(solid, camera, width, height, what);
    if (!(options.chordTolerance > 0.0 && options.chordTolerance <= 1.0))
        throw Error(ErrorKind::InvalidInput, what + ": chord tolerance " +
                                                 formatNumber(options.chordTolerance) + " is outside (0, 1]");
    if (!(std::isfinite(light.x) && std::isfinite(light.y) && std::isfinite(light.z)))
        throw Error(ErrorKind::InvalidInput, what + ": the light position is not finite");
    EmbreeErrors errors;
    GdmMeshReferenceStats counts;
    const WarpedScene warped =
        buildWarpedScene(solid, mesh, shell, options.chordTolerance, what, errors, counts);
    RTCDevice device = warped.periodic.device.get();
    const double H = warped.height;
    const double T = warped.thickness;

    GdmSceneImages images = detail::blankGdmImages(width, height);
    const double offset = kShadowOffsetTiles * T / H;
    std::atomic<std::size_t> exitFaces{0}, fromBelow{0};
    parallelFor(0, height, [&](int j) {
        for (int i = 0; i < width; ++i) {
            const glm::dvec3 direction = pixelRayDirection(camera, width, height, i + 0.5, j + 0.5);
            WarpedRayRule cameraRule;
            cameraRule.throughBase = options.throughBase;
            const WarpedCrossing hit = firstWarpedHit(warped, camera.eye, direction,
                                                      std::numeric_limits<double>::infinity(), cameraRule);
            if (hit.exitFace) exitFaces.fetch_add(1, std::memory_order_relaxed);
            if (!hit.found) continue;
            if (hit.fromBelow) fromBelow.fetch_add(1, std::memory_order_relaxed);
            const glm::dvec3 point = camera.eye + hit.t * direction;
            bool lit = false;
            if (glm::dot(hit.normal, light - point) > 0.0) {
                const glm::dvec3 origin = point + offset * hit.normal;
                const double reach = glm::length(light - origin);
                WarpedRayRule shadowRule;
                shadowRule.anySolidFace = true;
                lit = !firstWarpedHit(warped, origin, (light - origin) / reach, reach, shadowRule).found;
            }
            detail::writeGdmHit(images, i, j, hit.texture, H, lit);
        }
    });
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE || !errors.first.empty())
        throw Error(ErrorKind::Runtime, what + ": " + errors.first);
    counts.exitFaceCrossings = exitFaces.load();
    counts.hitsFromBelow = fromBelow.load();
    if (stats) *stats = counts;
    return images;
}

namespace {

void checkMasks(const Image& a, const Image& b, const char* what) {
    if (a.channels() != 1 || b.channels() != 1 || a.width() != b.width() || a.height() != b.height())
        throw Error(ErrorKind::InvalidInput,
                    std::string(what) + ": masks of " + std::to_string(a.width()) + " x " +
                        std::to_string(a.height()) + " x " + std::to_string(a.channels()) + " and " +
                        std::to_string(b.width()) + " x " + std::to_string(b.height()) + " x " +
                        std::to_string(b.channels()) + " (need the same size, 1 channel)");
}

bool inMask(const Image& mask, int x, int y) {
    return x >= 0 && y >= 0 && x < mask.width() && y < mask.height() && mask.at(x, y) > 0.5f;
}

std::vector<std::uint8_t> boundary(const Image& mask) {
    const int w = mask.width(), h = mask.height();
    std::vector<std::uint8_t> result(std::size_t(w) * std::size_t(h), 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (inMask(mask, x, y) && (!inMask(mask, x - 1, y) || !inMask(mask, x + 1, y) ||
                                       !inMask(mask, x, y - 1) || !inMask(mask, x, y + 1)))
                result[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1;
    return result;
}

// The exact squared Euclidean distance transform of a set of pixels (Felzenszwalb and Huttenlocher 2012,
// "Distance Transforms of Sampled Functions"): per pixel, the squared distance to the nearest pixel of the
// set (infinity where the set is empty).
std::vector<double> squaredDistance(const std::vector<std::uint8_t>& set, int w, int h) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::vector<double> grid(set.size());
    for (std::size_t k = 0; k < set.size(); ++k) grid[k] = set[k] ? 0.0 : kInf;
    const int n = std::max(w, h);
    std::vector<double> f(std::size_t(n) + 1), d(std::size_t(n) + 1), z(std::size_t(n) + 2);
    std::vector<int> v(std::size_t(n) + 1);
    // One dimension: d(q) = min_p (q - p)^2 + f(p), the lower envelope of the parabolas of the finite f(p).
    const auto transform = [&](int count) {
        int first = 0;
        while (first < count && f[std::size_t(first)] == kInf) ++first;
        if (first == count) {
            for (int q = 0; q < count; ++q) d[std::size_t(q)] = kInf;
            return;
        }
        const auto meet = [&](int q, int r) {
            return ((f[std::size_t(q)] + double(q) * q) - (f[std::size_t(r)] + double(r) * r)) /
                   (2.0 * (q - r));
        };
        std::size_t k = 0;
        v[0] = first;
        z[0] = -kInf;
        z[1] = kInf;
        for (int q = first + 1; q < count; ++q) {
            if (f[std::size_t(q)] == kInf) continue;
            double s = meet(q, v[k]);
            while (s <= z[k]) {  // never past k = 0: z[0] is -infinity
                --k;
                s = meet(q, v[k]);
            }
            ++k;
            v[k] = q;
            z[k] = s;
            z[k + 1] = kInf;
        }
        k = 0;
        for (int q = 0; q < count; ++q) {
            while (z[k + 1] < q) ++k;
            const int p = v[k];
            d[std::size_t(q)] = double(q - p) * double(q - p) + f[std::size_t(p)];
        }
    };
    for (int x = 0; x < w; ++x) {
        for (int y = 0; y < h; ++y)
            f[std::size_t(y)] = grid[std::size_t(y) * std::size_t(w) + std::size_t(x)];
        transform(h);
        for (int y = 0; y < h; ++y)
            grid[std::size_t(y) * std::size_t(w) + std::size_t(x)] = d[std::size_t(y)];
    }
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x)
            f[std::size_t(x)] = grid[std::size_t(y) * std::size_t(w) + std::size_t(x)];
        transform(w);
        for (int x = 0; x < w; ++x)
            grid[std::size_t(y) * std::size_t(w) + std::size_t(x)] = d[std::size_t(x)];
    }
    return grid;
}

// max over the pixels of `from` of the distance to the nearest pixel of `to` (given as its transform).
double directed(const std::vector<std::uint8_t>& from, const std::vector<double>& toDistance) {
    double worst = 0.0;
    for (std::size_t k = 0; k < from.size(); ++k)
        if (from[k]) worst = std::max(worst, toDistance[k]);
    return std::sqrt(worst);
}

}  // namespace

double silhouetteIoU(const Image& maskA, const Image& maskB) {
    checkMasks(maskA, maskB, "silhouette IoU");
    std::size_t both = 0, either = 0;
    for (int y = 0; y < maskA.height(); ++y)
        for (int x = 0; x < maskA.width(); ++x) {
            const bool a = maskA.at(x, y) > 0.5f, b = maskB.at(x, y) > 0.5f;
            both += a && b;
            either += a || b;
        }
    return either == 0 ? 1.0 : double(both) / double(either);
}

double silhouetteHausdorff(const Image& maskA, const Image& maskB) {
    checkMasks(maskA, maskB, "silhouette Hausdorff distance");
    const int w = maskA.width(), h = maskA.height();
    const std::vector<std::uint8_t> a = boundary(maskA), b = boundary(maskB);
    const bool emptyA = std::find(a.begin(), a.end(), 1) == a.end();
    const bool emptyB = std::find(b.begin(), b.end(), 1) == b.end();
    if (emptyA && emptyB) return 0.0;
    if (emptyA || emptyB) return std::numeric_limits<double>::infinity();
    return std::max(directed(a, squaredDistance(b, w, h)), directed(b, squaredDistance(a, w, h)));
}

}  // namespace strata
