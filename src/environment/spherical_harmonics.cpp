#include "strata/environment/spherical_harmonics.h"

#include "strata/core/check.h"

#include <boost/math/quadrature/gauss.hpp>
#include <glm/geometric.hpp>

#include <cmath>

namespace strata {

namespace {

constexpr double kPi = std::numbers::pi;

glm::dvec3 normalizedDirection(const glm::dvec3& direction) {
    const double length = glm::length(direction);
    STRATA_CHECK(std::isfinite(length) && length > 0.0);
    return direction / length;
}

SphereQuadrature makeShQuadrature() {
    // Boost.Math tabulates the non-negative nodes of the 20-point rule on [-1, 1] (and their weights);
    // mapped to [0, 1] and [-1, 0] they give one 20-point rule per hemisphere.
    constexpr int kNodes = 20;
    constexpr int kAzimuths = 64;
    using Rule = boost::math::quadrature::gauss<double, kNodes>;
    const auto& abscissa = Rule::abscissa();
    const auto& weight = Rule::weights();
    std::vector<double> nodes;  // on [-1, 1]
    std::vector<double> nodeWeights;
    for (std::size_t i = 0; i < abscissa.size(); ++i) {
        nodes.push_back(abscissa[i]);
        nodeWeights.push_back(weight[i]);
        if (abscissa[i] != 0.0) {
            nodes.push_back(-abscissa[i]);
            nodeWeights.push_back(weight[i]);
        }
    }
    STRATA_CHECK_EQ(nodes.size(), std::size_t{kNodes});
    SphereQuadrature rule;
    for (const double hemisphere : {1.0, -1.0}) {
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            // z = hemisphere * (node + 1) / 2; dz = dnode / 2; the azimuth integral is 2 pi / kAzimuths per
            // sample.
            const double z = hemisphere * 0.5 * (nodes[i] + 1.0);
            const double sinPolar = std::sqrt(std::max(0.0, 1.0 - z * z));
            const double w = 0.5 * nodeWeights[i] * 2.0 * kPi / kAzimuths;
            for (int a = 0; a < kAzimuths; ++a) {
                const double azimuth = (a + 0.5) * 2.0 * kPi / kAzimuths;
                rule.directions.emplace_back(sinPolar * std::cos(azimuth), sinPolar * std::sin(azimuth), z);
                rule.weights.push_back(w);
            }
        }
    }
    return rule;
}

}  // namespace

ShVector shEvaluate(const glm::dvec3& direction) {
    static const double k0 = 0.5 * std::sqrt(1.0 / kPi);
    static const double k1 = std::sqrt(3.0 / (4.0 * kPi));
    static const double k2a = 0.5 * std::sqrt(15.0 / kPi);
    static const double k20 = 0.25 * std::sqrt(5.0 / kPi);
    static const double k22 = 0.25 * std::sqrt(15.0 / kPi);
    static const double k33 = 0.25 * std::sqrt(35.0 / (2.0 * kPi));
    static const double k32a = 0.5 * std::sqrt(105.0 / kPi);
    static const double k31 = 0.25 * std::sqrt(21.0 / (2.0 * kPi));
    static const double k30 = 0.25 * std::sqrt(7.0 / kPi);
    static const double k32b = 0.25 * std::sqrt(105.0 / kPi);
    const glm::dvec3 d = normalizedDirection(direction);
    const double x = d.x, y = d.y, z = d.z;
    const double z2 = z * z;
    return {
        k0,
        k1 * y,
        k1 * z,
        k1 * x,
        k2a * x * y,
        k2a * y * z,
        k20 * (3.0 * z2 - 1.0),
        k2a * x * z,
        k22 * (x * x - y * y),
        k33 * y * (3.0 * x * x - y * y),
        k32a * x * y * z,
        k31 * y * (5.0 * z2 - 1.0),
        k30 * z * (5.0 * z2 - 3.0),
        k31 * x * (5.0 * z2 - 1.0),
        k32b * z * (x * x - y * y),
        k33 * x * (x * x - 3.0 * y * y),
    };
}

double shReconstruct(const ShVector& coefficients, const glm::dvec3& direction) {
    const ShVector basis = shEvaluate(direction);
    double sum = 0.0;
    for (int k = 0; k < kShCount; ++k) sum += coefficients[k] * basis[k];
    return sum;
}

glm::dvec3 shReconstruct(const ShColor& coefficients, const glm::dvec3& direction) {
    const ShVector basis = shEvaluate(direction);
    glm::dvec3 sum(0.0);
    for (int k = 0; k < kShCount; ++k) sum += coefficients[k] * basis[k];
    return sum;
}

const SphereQuadrature& shQuadrature() {
    static const SphereQuadrature rule = makeShQuadrature();
    return rule;
}

ShVector shProject(const std::function<double(const glm::dvec3&)>& function) {
    const SphereQuadrature& rule = shQuadrature();
    ShVector result{};
    for (std::size_t i = 0; i < rule.directions.size(); ++i) {
        const ShVector basis = shEvaluate(rule.directions[i]);
        const double value = function(rule.directions[i]) * rule.weights[i];
        for (int k = 0; k < kShCount; ++k) result[k] += value * basis[k];
    }
    return result;
}

ShColor shProject(const std::function<glm::dvec3(const glm::dvec3&)>& function) {
    const SphereQuadrature& rule = shQuadrature();
    ShColor result{};
    for (std::size_t i = 0; i < rule.directions.size(); ++i) {
        const ShVector basis = shEvaluate(rule.directions[i]);
        const glm::dvec3 value = function(rule.directions[i]) * rule.weights[i];
        for (int k = 0; k < kShCount; ++k) result[k] += value * basis[k];
    }
    return result;
}

ShColor shIrradiance(const ShColor& radiance) {
    ShColor result;
    for (int k = 0; k < kShCount; ++k) result[k] = kClampedCosineBands[shBand(k)] * radiance[k];
    return result;
}

ShVector shLuminance(const ShColor& coefficients) {
    ShVector result;
    for (int k = 0; k < kShCount; ++k)
        result[k] = glm::dot(coefficients[k], glm::dvec3(0.2126, 0.7152, 0.0722));
    return result;
}

glm::dvec3 shDominantDirection(const ShVector& coefficients) {
    const glm::dvec3 band1(coefficients[3], coefficients[1], coefficients[2]);
    const double length = glm::length(band1);
    return length > 0.0 ? band1 / length : glm::dvec3(0.0);
}

}  // namespace strata
