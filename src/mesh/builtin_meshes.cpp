#include "strata/mesh/builtin_meshes.h"

#include "strata/core/error.h"
#include "strata/mesh/mesh_repair.h"
#include "strata/mesh/teapot.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace strata {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kMaxTessellation = 256;

// An analytic surface sample: position, outward normal, a tangent along increasing u and a vector along
// increasing v (only its side matters: it sets the handedness).
struct Sample {
    glm::dvec3 position;
    glm::dvec3 normal;
    glm::dvec3 dpdu;
    glm::dvec3 dpdv;
    glm::dvec2 uv;
};

MeshVertex toVertex(const Sample& s) {
    const glm::dvec3 n = glm::normalize(s.normal);
    const glm::dvec3 t = glm::normalize(s.dpdu - n * glm::dot(n, s.dpdu));
    const double w = glm::dot(glm::cross(n, t), s.dpdv) < 0.0 ? -1.0 : 1.0;
    MeshVertex v;
    v.position = glm::vec3(s.position);
    v.normal = glm::vec3(n);
    v.uv = glm::vec2(s.uv);
    v.tangent = glm::vec4(glm::vec3(t), static_cast<float>(w));
    return v;
}

// Appends an (nu + 1) x (nv + 1) grid of samples f(i, j), vertex (i, j) at base + j * (nu + 1) + i, and two
// counter-clockwise triangles per cell (counter-clockwise in uv is counter-clockwise seen from the normal
// when N = T x B). Triangles with two corners at the same position (a grid edge collapsed to a point: a
// pole) are left out.
void appendGrid(Mesh& mesh, int nu, int nv, const std::function<Sample(int, int)>& f) {
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    for (int j = 0; j <= nv; ++j) {
        for (int i = 0; i <= nu; ++i) mesh.vertices.push_back(toVertex(f(i, j)));
    }
    const auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * (nu + 1) + i); };
    const auto addTriangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        const glm::vec3 &pa = mesh.vertices[a].position, &pb = mesh.vertices[b].position,
                        &pc = mesh.vertices[c].position;
        if (pa == pb || pb == pc || pa == pc) return;
        mesh.indices.insert(mesh.indices.end(), {a, b, c});
    };
    for (int j = 0; j < nv; ++j) {
        for (int i = 0; i < nu; ++i) {
            addTriangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            addTriangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
}

double frac(int i, int n) {
    return static_cast<double>(i) / static_cast<double>(n);
}

// --- teapot -------------------------------------------------------------------------------------------

struct PatchEval {
    glm::dvec3 p, ps, pt, pst;
};

void bernstein(double u, double b[4], double db[4]) {
    const double v = 1.0 - u;
    b[0] = v * v * v;
    b[1] = 3.0 * u * v * v;
    b[2] = 3.0 * u * u * v;
    b[3] = u * u * u;
    db[0] = -3.0 * v * v;
    db[1] = 3.0 * v * v - 6.0 * u * v;
    db[2] = 6.0 * u * v - 3.0 * u * u;
    db[3] = 3.0 * u * u;
}

PatchEval evalPatch(const std::array<glm::vec3, 16>& c, double s, double t) {
    double bs[4], dbs[4], bt[4], dbt[4];
    bernstein(s, bs, dbs);
    bernstein(t, bt, dbt);
    PatchEval e{};
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            const glm::dvec3 cp(c[static_cast<std::size_t>(4 * j + i)]);
            e.p += bs[i] * bt[j] * cp;
            e.ps += dbs[i] * bt[j] * cp;
            e.pt += bs[i] * dbt[j] * cp;
            e.pst += dbs[i] * dbt[j] * cp;
        }
    }
    return e;
}

// Below this |dP/ds| (teapot height 1; regular patches have |dP/ds| > 0.01) an edge has collapsed to a point.
constexpr double kCollapsed = 1e-9;

Sample teapotSample(const std::array<glm::vec3, 16>& c, double s, double t) {
    const PatchEval e = evalPatch(c, s, t);
    glm::dvec3 ps = e.ps, pt = e.pt;
    // On a collapsed edge t = 0 (or 1), dP/ds = 0, but dP/ds = t * d2P/dsdt + O(t^2) next to it: the limit
    // direction of dP/ds is +-d2P/dsdt, and with it the limit of the normal cross(dP/ds, dP/dt).
    if (glm::length(ps) < kCollapsed) ps = (t < 0.5 ? 1.0 : -1.0) * e.pst;
    if (glm::length(pt) < kCollapsed) pt = (s < 0.5 ? 1.0 : -1.0) * e.pst;
    return Sample{e.p, glm::cross(ps, pt), ps, pt, glm::dvec2(s, t)};
}

Mesh makeTeapot(int n) {
    Mesh mesh;
    for (int patch = 0; patch < kTeapotPatchCount; ++patch) {
        const std::array<glm::vec3, 16> c = teapotPatchControlPoints(patch);
        appendGrid(mesh, n, n, [&](int i, int j) { return teapotSample(c, frac(i, n), frac(j, n)); });
    }
    return mesh;
}

// --- simple solids ------------------------------------------------------------------------------------

Mesh makeCube(int n) {
    struct Face {
        glm::dvec3 normal, tangent, bitangent;
    };
    // T x B = N on every face; side faces have v up (+z), the top u = +x, v = +y, the bottom u = +x, v = -y.
    const Face faces[6] = {
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}},
        {{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {1, 0, 0}, {0, -1, 0}},
    };
    Mesh mesh;
    for (const Face& face : faces) {
        appendGrid(mesh, n, n, [&](int i, int j) {
            const double u = frac(i, n), v = frac(j, n);
            const glm::dvec3 p = 0.5 * face.normal + (u - 0.5) * face.tangent + (v - 0.5) * face.bitangent;
            return Sample{p, face.normal, face.tangent, face.bitangent, {u, v}};
        });
    }
    return mesh;
}

Mesh makeSphere(int n) {
    constexpr double kRadius = 0.5;
    const int nu = 4 * n, nv = 2 * n;
    Mesh mesh;
    appendGrid(mesh, nu, nv, [&](int i, int j) {
        double u = frac(i, nu);
        const double v = frac(j, nv);
        // A pole vertex serves one triangle: (i, 0) that of cell i, (i, nv) that of cell i - 1. Give it the u
        // (and tangent) of that cell's middle; (nu, 0) and (0, nv) serve none and are removed below.
        if (j == 0) u += 0.5 / nu;
        if (j == nv) u -= 0.5 / nu;
        const double phi = kTwoPi * u, lat = std::numbers::pi * (v - 0.5);
        const glm::dvec3 n3(std::cos(lat) * std::cos(phi), std::cos(lat) * std::sin(phi), std::sin(lat));
        const glm::dvec3 east(-std::sin(phi), std::cos(phi), 0.0);
        const glm::dvec3 north(-std::sin(lat) * std::cos(phi), -std::sin(lat) * std::sin(phi), std::cos(lat));
        return Sample{kRadius * n3, n3, east, north, {u, v}};
    });
    // The pole rows have one vertex too many, used by no triangle.
    repairMesh(mesh);
    return mesh;
}

Mesh makeTorus(int n) {
    constexpr double kMajor = 0.35, kMinor = 0.15;
    const int nu = 4 * n, nv = 4 * n;
    Mesh mesh;
    appendGrid(mesh, nu, nv, [&](int i, int j) {
        const double u = frac(i, nu), v = frac(j, nv);
        const double phi = kTwoPi * u, theta = kTwoPi * v;
        const glm::dvec3 radial(std::cos(phi), std::sin(phi), 0.0);
        const glm::dvec3 n3 = std::cos(theta) * radial + glm::dvec3(0, 0, std::sin(theta));
        const glm::dvec3 p = kMajor * radial + kMinor * n3;
        const glm::dvec3 east(-std::sin(phi), std::cos(phi), 0.0);
        const glm::dvec3 up = -std::sin(theta) * radial + glm::dvec3(0, 0, std::cos(theta));
        return Sample{p, n3, east, up, {u, v}};
    });
    return mesh;
}

Mesh makeCylinder(int n) {
    constexpr double kRadius = 0.5;
    const int around = 4 * n;
    Mesh mesh;
    appendGrid(mesh, around, n, [&](int i, int j) {
        const double u = frac(i, around), v = frac(j, n);
        const double phi = kTwoPi * u;
        const glm::dvec3 radial(std::cos(phi), std::sin(phi), 0.0);
        const glm::dvec3 p = kRadius * radial + glm::dvec3(0, 0, v - 0.5);
        return Sample{p, radial, {-std::sin(phi), std::cos(phi), 0.0}, {0, 0, 1}, {u, v}};
    });
    // Caps: fans around a centre vertex, planar uvs that read upright from outside.
    for (const double side : {1.0, -1.0}) {
        const auto centre = static_cast<std::uint32_t>(mesh.vertices.size());
        const glm::dvec3 normal(0, 0, side), tangent(1, 0, 0), bitangent(0, side, 0);
        const auto capSample = [&](const glm::dvec3& p) {
            return toVertex(Sample{p, normal, tangent, bitangent, {p.x + 0.5, 0.5 + side * p.y}});
        };
        mesh.vertices.push_back(capSample({0, 0, 0.5 * side}));
        for (int i = 0; i < around; ++i) {
            const double phi = kTwoPi * frac(i, around);
            mesh.vertices.push_back(
                capSample({kRadius * std::cos(phi), kRadius * std::sin(phi), 0.5 * side}));
        }
        for (int i = 0; i < around; ++i) {
            const std::uint32_t a = centre + 1 + static_cast<std::uint32_t>(i);
            const std::uint32_t b = centre + 1 + static_cast<std::uint32_t>((i + 1) % around);
            // Counter-clockwise about +z for the top, clockwise (so counter-clockwise from below) for the
            // bottom.
            if (side > 0.0) {
                mesh.indices.insert(mesh.indices.end(), {centre, a, b});
            } else {
                mesh.indices.insert(mesh.indices.end(), {centre, b, a});
            }
        }
    }
    return mesh;
}

// The vase's profile: radius r(t) and its derivative at height fraction t in [0, 1] (z = t - 0.5): a foot,
// a round belly and a flared neck.
constexpr double kVaseBelly = 0.16, kVaseBase = 0.22;
double vaseRadius(double t) {
    return kVaseBase + kVaseBelly * std::sin(std::numbers::pi * t) + 0.12 * t * t * t;
}
double vaseRadiusSlope(double t) {
    return kVaseBelly * std::numbers::pi * std::cos(std::numbers::pi * t) + 0.36 * t * t;
}

Mesh makeVase(int n) {
    const int around = 4 * n, along = 2 * n;
    // v is the profile's arc length over the mean circumference, so that a uv square is about square in
    // world units; the arc length by the trapezoid rule on a fine grid.
    constexpr int kArcSteps = 4096;
    std::vector<double> arc(kArcSteps + 1, 0.0);
    double meanRadius = 0.0;
    for (int k = 1; k <= kArcSteps; ++k) {
        const double t0 = frac(k - 1, kArcSteps), t1 = frac(k, kArcSteps);
        arc[std::size_t(k)] = arc[std::size_t(k - 1)] + std::hypot(vaseRadius(t1) - vaseRadius(t0), t1 - t0);
        meanRadius += 0.5 * (vaseRadius(t0) + vaseRadius(t1)) / kArcSteps;
    }
    const double circumference = kTwoPi * meanRadius;
    const auto arcAt = [&](double t) {
        const double x = t * kArcSteps;
        const int k = std::min(int(x), kArcSteps - 1);
        return arc[std::size_t(k)] + (x - k) * (arc[std::size_t(k + 1)] - arc[std::size_t(k)]);
    };
    Mesh mesh;
    appendGrid(mesh, around, along, [&](int i, int j) {
        const double u = frac(i, around), t = frac(j, along);
        // The seam's two columns of vertices at exactly the same positions (u = 1 at phi = 0).
        const double phi = kTwoPi * frac(i % around, around), r = vaseRadius(t), slope = vaseRadiusSlope(t);
        const glm::dvec3 radial(std::cos(phi), std::sin(phi), 0.0);
        const glm::dvec3 p = r * radial + glm::dvec3(0, 0, t - 0.5);
        const glm::dvec3 normal = radial - glm::dvec3(0, 0, slope);
        const glm::dvec3 up = slope * radial + glm::dvec3(0, 0, 1);
        return Sample{p, normal, {-std::sin(phi), std::cos(phi), 0.0}, up, {u, arcAt(t) / circumference}};
    });
    return mesh;
}

// A cylindrical arc of radius 0.6 over 120 degrees about the y axis, 1 wide: a curved, open patch.
Mesh makePatch(int n) {
    constexpr double kRadius = 0.6, kHalfAngle = std::numbers::pi / 3.0;
    const int across = 2 * n, along = 2 * n;
    Mesh mesh;
    appendGrid(mesh, across, along, [&](int i, int j) {
        const double a = (2.0 * frac(i, across) - 1.0) * kHalfAngle, y = frac(j, along) - 0.5;
        const glm::dvec3 normal(std::sin(a), 0.0, std::cos(a));
        const glm::dvec3 p(kRadius * std::sin(a), y, kRadius * (std::cos(a) - 1.0));
        // uv in world units: the arc length from the patch's -x edge, and y + 0.5.
        return Sample{
            p, normal, {std::cos(a), 0.0, -std::sin(a)}, {0, 1, 0}, {kRadius * (a + kHalfAngle), y + 0.5}};
    });
    return mesh;
}

// The trunk (builtin_meshes.h): an axis bent in an S in x, a radius that tapers with height, flares out
// towards the ground and has a few low lumps around; horizontal rings of vertices. All of it analytic, with
// derivatives: P(theta, z) = axis(z) + r(theta, z) (cos theta, sin theta, 0), N = dP/dtheta x dP/dz
// = r radial - dr/dtheta east - (...) z, so N . radial = r > 0: outward.
constexpr double kTrunkHeight = 2.0;
constexpr double kTrunkBend = 0.05;   // the axis: x(z) = kTrunkBend sin(pi z)
constexpr double kTrunkTaper = 0.09;  // rho(z) = (1 + kTrunkTaper (1 - z)) / pi
constexpr double kTrunkFlare = 0.3;   // f(z) = 1 + kTrunkFlare exp(-z / kTrunkFlareHeight)
constexpr double kTrunkFlareHeight = 0.12;
constexpr double kTrunkRootLobes = 0.06;  // 5 root lobes: kTrunkRootLobes exp(-z / kTrunkRootHeight)
constexpr double kTrunkRootHeight = 0.25;
// u = the angle times kTrunkReferenceRadius: the arc length on the circle of circumference 2 (about the
// trunk's radius at z = 1 without lumps), u in [0, 2].
constexpr double kTrunkCircumference = 2.0;
constexpr double kTrunkReferenceRadius = kTrunkCircumference / kTwoPi;

double trunkAxisSlope(double z) {
    return kTrunkBend * std::numbers::pi * std::cos(std::numbers::pi * z);
}

// The lump-free radius R(z) = rho(z) f(z) and its derivative.
glm::dvec2 trunkMeanRadius(double z) {
    const double rho = (1.0 + kTrunkTaper * (1.0 - z)) / std::numbers::pi,
                 drho = -kTrunkTaper / std::numbers::pi;
    const double e = std::exp(-z / kTrunkFlareHeight);
    const double f = 1.0 + kTrunkFlare * e, df = -kTrunkFlare / kTrunkFlareHeight * e;
    return {rho * f, drho * f + rho * df};
}

// The lumps L(theta, z) (the radius is R(z) (1 + L)) and its derivatives along theta and z.
glm::dvec3 trunkLumps(double theta, double z) {
    const double a = 3.0 * theta + 1.1 * z, b = 7.0 * theta - 2.3 * z;
    const double lobes = kTrunkRootLobes * std::exp(-z / kTrunkRootHeight);
    const double l = 0.02 * std::cos(a) + 0.015 * std::sin(b) + lobes * std::cos(5.0 * theta);
    const double dTheta = -0.06 * std::sin(a) + 0.105 * std::cos(b) - 5.0 * lobes * std::sin(5.0 * theta);
    const double dz =
        -0.022 * std::sin(a) - 0.0345 * std::cos(b) - lobes / kTrunkRootHeight * std::cos(5.0 * theta);
    return {l, dTheta, dz};
}

// dv/dz: v measures height in the local scale of u (R(z) / kTrunkReferenceRadius per unit of u), so that the
// lump-free trunk's uv map is conformal; the axis' lean counts as it does on average around the trunk.
double trunkDvDz(double z) {
    const glm::dvec2 r = trunkMeanRadius(z);
    const double slope = trunkAxisSlope(z);
    return kTrunkReferenceRadius * std::sqrt(1.0 + slope * slope + r.y * r.y) / r.x;
}

Mesh makeTrunk(int n) {
    const int around = 4 * n, along = 4 * n;
    // v at each row: Simpson's rule on 16 sub-intervals per row (the integrand is smooth: the rows of the
    // coarsest trunk and of n = 16 at the same heights agree to float rounding, tests).
    std::vector<double> rowV(std::size_t(along) + 1, 0.0);
    constexpr int kSub = 16;
    for (int j = 1; j <= along; ++j) {
        const double z0 = kTrunkHeight * frac(j - 1, along), h = kTrunkHeight / along / kSub;
        double sum = trunkDvDz(z0) + trunkDvDz(z0 + kSub * h);
        for (int k = 1; k < kSub; ++k) sum += (k % 2 == 1 ? 4.0 : 2.0) * trunkDvDz(z0 + k * h);
        rowV[std::size_t(j)] = rowV[std::size_t(j - 1)] + sum * h / 3.0;
    }
    Mesh mesh;
    appendGrid(mesh, around, along, [&](int i, int j) {
        // The seam's two columns of vertices at exactly the same positions (theta = 2 pi is evaluated at 0).
        const double theta = kTwoPi * frac(i % around, around), z = kTrunkHeight * frac(j, along);
        const glm::dvec2 mean = trunkMeanRadius(z);
        const glm::dvec3 lumps = trunkLumps(theta, z);
        const double r = mean.x * (1.0 + lumps.x), drdTheta = mean.x * lumps.y;
        const double drdz = mean.y * (1.0 + lumps.x) + mean.x * lumps.z;
        const glm::dvec3 radial(std::cos(theta), std::sin(theta), 0.0),
            east(-std::sin(theta), std::cos(theta), 0.0);
        const glm::dvec3 axis(kTrunkBend * std::sin(std::numbers::pi * z), 0.0, z);
        const glm::dvec3 p = axis + r * radial;
        const glm::dvec3 dpdTheta = drdTheta * radial + r * east;
        const glm::dvec3 dpdz = glm::dvec3(trunkAxisSlope(z), 0.0, 1.0) + drdz * radial;
        const double u = kTrunkCircumference * frac(i, around);
        return Sample{p, glm::cross(dpdTheta, dpdz), dpdTheta, dpdz, {u, rowV[std::size_t(j)]}};
    });
    return mesh;
}

Mesh makePlane(int n) {
    Mesh mesh;
    appendGrid(mesh, n, n, [&](int i, int j) {
        const double u = frac(i, n), v = frac(j, n);
        return Sample{{2.0 * u - 1.0, 2.0 * v - 1.0, 0.0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {u, v}};
    });
    return mesh;
}

// CONVENTIONS §7, written out literally: no arithmetic that could round.
Mesh makeQuad() {
    Mesh mesh;
    const glm::vec4 tangent(1.0f, 0.0f, 0.0f, 1.0f);
    const glm::vec3 normal(0.0f, 0.0f, 1.0f);
    mesh.vertices = {
        {{0.0f, 0.0f, 0.0f}, normal, {0.0f, 0.0f}, tangent},
        {{1.0f, 0.0f, 0.0f}, normal, {1.0f, 0.0f}, tangent},
        {{1.0f, 1.0f, 0.0f}, normal, {1.0f, 1.0f}, tangent},
        {{0.0f, 1.0f, 0.0f}, normal, {0.0f, 1.0f}, tangent},
    };
    mesh.indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

}  // namespace

std::vector<std::string> builtinMeshList() {
    return {"teapot", "cube", "sphere", "torus", "cylinder", "vase", "patch", "trunk", "plane", "quad"};
}

Mesh makeBuiltinMesh(const std::string& name, const BuiltinMeshParams& params) {
    const int n = params.tessellation;
    if (n < 1 || n > kMaxTessellation) {
        throw Error(ErrorKind::InvalidInput, "built-in mesh '" + name + "': tessellation " +
                                                 std::to_string(n) + " is outside [1, " +
                                                 std::to_string(kMaxTessellation) + "]");
    }
    Mesh mesh;
    if (name == "teapot") {
        mesh = makeTeapot(n);
    } else if (name == "cube") {
        mesh = makeCube(n);
    } else if (name == "sphere") {
        mesh = makeSphere(n);
    } else if (name == "torus") {
        mesh = makeTorus(n);
    } else if (name == "cylinder") {
        mesh = makeCylinder(n);
    } else if (name == "vase") {
        mesh = makeVase(n);
    } else if (name == "patch") {
        mesh = makePatch(n);
    } else if (name == "trunk") {
        mesh = makeTrunk(n);
    } else if (name == "plane") {
        mesh = makePlane(n);
    } else if (name == "quad") {
        mesh = makeQuad();
    } else {
        std::string known;
        for (const std::string& k : builtinMeshList()) known += (known.empty() ? "" : ", ") + k;
        throw Error(ErrorKind::InvalidInput, "unknown built-in mesh '" + name + "' (known: " + known + ")");
    }
    mesh.name = name;
    return mesh;
}

}  // namespace strata
