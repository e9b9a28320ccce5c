// The built-in procedural skies (environment.h lists them with their parameters). Stylised, not measured
// data, except sky-overcast, which is the CIE standard overcast sky (Moon & Spencer 1942, CIE S 011/E:2003
// type 1): L(t) = L_z (1 + 2 cos t) / 3.
#include "strata/core/error.h"
#include "strata/environment/environment.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace strata {

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

glm::dvec3 elevationAzimuth(double elevationDegrees, double azimuthDegrees) {
    return sphericalDirection((90.0 - elevationDegrees) * kDegree, azimuthDegrees * kDegree);
}

// 1 inside a round disc of angular radius `radius` around `centre`, 0 outside, with a linear edge `soft`
// radians wide (centred on the radius) so that the disc is continuous.
double disc(const glm::dvec3& direction, const glm::dvec3& centre, double radius, double soft) {
    const double angle = std::acos(std::clamp(glm::dot(direction, centre), -1.0, 1.0));
    return std::clamp((radius + 0.5 * soft - angle) / soft, 0.0, 1.0);
}

glm::dvec3 skyClear(const glm::dvec3& direction) {
    const glm::dvec3 d = glm::normalize(direction);
    static const glm::dvec3 sun = elevationAzimuth(35.0, 60.0);
    if (d.z < 0.0) return {0.22, 0.20, 0.17};
    const glm::dvec3 zenith(0.20, 0.40, 0.85);
    const glm::dvec3 horizon(0.80, 0.88, 1.00);
    glm::dvec3 sky = glm::mix(horizon, zenith, std::pow(d.z, 0.5));
    const double towardsSun = std::max(0.0, glm::dot(d, sun));
    sky += glm::dvec3(1.0, 0.9, 0.7) * (0.6 * std::pow(towardsSun, 32.0));
    return sky + glm::dvec3(1.0, 0.96, 0.9) * (800.0 * disc(d, sun, 2.0 * kDegree, 0.5 * kDegree));
}

glm::dvec3 skyOvercast(const glm::dvec3& direction) {
    const glm::dvec3 d = glm::normalize(direction);
    // Ground: a Lambertian of albedo 0.2 lit by the sky's horizontal irradiance 7 pi / 9: 0.2 * 7 / 9.
    if (d.z < 0.0) return glm::dvec3(0.2 * 7.0 / 9.0);
    return glm::dvec3((1.0 + 2.0 * d.z) / 3.0);
}

glm::dvec3 skySunset(const glm::dvec3& direction) {
    const glm::dvec3 d = glm::normalize(direction);
    static const glm::dvec3 sun = elevationAzimuth(3.0, 250.0);
    if (d.z < 0.0) return {0.05, 0.04, 0.04};
    // The horizon is warm towards the sun and mauve away from it.
    const glm::dvec3 horizontalSun = glm::normalize(glm::dvec3(sun.x, sun.y, 0.0));
    const glm::dvec3 horizontal(d.x, d.y, 0.0);
    const double facing =
        glm::length(horizontal) > 0.0 ? 0.5 + 0.5 * glm::dot(glm::normalize(horizontal), horizontalSun) : 0.5;
    const glm::dvec3 horizon =
        glm::mix(glm::dvec3(0.45, 0.35, 0.50), glm::dvec3(1.40, 0.60, 0.25), facing * facing);
    const glm::dvec3 zenith(0.08, 0.12, 0.30);
    glm::dvec3 sky = glm::mix(horizon, zenith, std::pow(d.z, 0.35));
    const double towardsSun = std::max(0.0, glm::dot(d, sun));
    sky += glm::dvec3(1.5, 0.6, 0.2) * (1.0 * std::pow(towardsSun, 16.0));
    return sky + glm::dvec3(1.0, 0.55, 0.25) * (300.0 * disc(d, sun, 1.5 * kDegree, 0.5 * kDegree));
}

glm::dvec3 studio(const glm::dvec3& direction) {
    const glm::dvec3 d = glm::normalize(direction);
    static const glm::dvec3 key = elevationAzimuth(40.0, -45.0);
    static const glm::dvec3 fill = elevationAzimuth(15.0, 150.0);
    static const glm::dvec3 rim = elevationAzimuth(70.0, 200.0);
    // Walls a little lighter towards the ceiling; a darker floor.
    glm::dvec3 value = d.z < 0.0 ? glm::dvec3(0.03) : glm::dvec3(0.05 + 0.03 * d.z);
    value += glm::dvec3(6.0) * disc(d, key, 12.0 * kDegree, 1.0 * kDegree);
    value += glm::dvec3(1.08, 1.14, 1.2) * disc(d, fill, 18.0 * kDegree, 1.0 * kDegree);
    value += glm::dvec3(3.0) * disc(d, rim, 8.0 * kDegree, 1.0 * kDegree);
    return value;
}

struct Sky {
    const char* name;
    glm::dvec3 (*radiance)(const glm::dvec3&);
};

constexpr Sky kSkies[] = {
    {"sky-clear", skyClear},
    {"sky-overcast", skyOvercast},
    {"sky-sunset", skySunset},
    {"studio", studio},
};

}  // namespace

std::vector<std::string> environmentList() {
    std::vector<std::string> names;
    for (const Sky& sky : kSkies) names.emplace_back(sky.name);
    return names;
}

RadianceFunction skyRadiance(const std::string& name) {
    for (const Sky& sky : kSkies)
        if (name == sky.name) return sky.radiance;
    std::string list;
    for (const Sky& sky : kSkies) list += (list.empty() ? "" : ", ") + std::string(sky.name);
    throw Error(ErrorKind::InvalidInput, "unknown environment '" + name + "': the built-in ones are " + list);
}

}  // namespace strata
