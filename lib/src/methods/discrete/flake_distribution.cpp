#include "methods/discrete/flake_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace glintscope {

double vertex_rule(const NormalDensity& density, const SphericalTriangle& t) {
    return solid_angle(t) * (density(t.v[0]) + density(t.v[1]) + density(t.v[2])) / 3.0;
}

std::array<DirectionCell, 4> split(const DirectionCell& cell, const NormalDensity& density) {
    std::array<DirectionCell, 4> children;
    if (cell.label == kHemisphereLabel) {
        const std::array<SphericalTriangle, 4> quadrants = hemisphere_quadrants();
        const double pole = density(Vec3{0, 0, 1});
        for (int j = 0; j < 4; ++j) {
            children[j].triangle = quadrants[j];
            children[j].density = {density(quadrants[j].v[0]), density(quadrants[j].v[1]), pole};
        }
    } else {
        const std::array<SphericalTriangle, 4> triangles = split(cell.triangle);
        // split() puts the midpoints m01, m12, m20 at these places (see its order).
        const double d01 = density(triangles[3].v[0]), d12 = density(triangles[3].v[1]), d20 = density(triangles[3].v[2]);
        const std::array<double, 3>& d = cell.density;
        const std::array<std::array<double, 3>, 4> densities = {
            std::array<double, 3>{d[0], d01, d20}, std::array<double, 3>{d01, d[1], d12},
            std::array<double, 3>{d20, d12, d[2]}, std::array<double, 3>{d01, d12, d20}};
        for (int j = 0; j < 4; ++j) {
            children[j].triangle = triangles[j];
            children[j].density = densities[j];
        }
    }
    for (int j = 0; j < 4; ++j) {
        children[j].solid_angle = solid_angle(children[j].triangle);
        children[j].label = child_label(cell.label, j + 1);
        children[j].depth = cell.depth + 1;
    }
    return children;
}

double TriangleIntegrals::integral(const DirectionCell& cell) const {
    const auto entry = table.find(cell.label);
    if (entry != table.end()) return entry->second;
    return cell.solid_angle * (cell.density[0] + cell.density[1] + cell.density[2]) / 3.0;
}

double cell_share(const SphericalConic& conic, const DirectionCell& cell, double reference_solid_angle) {
    const double share = inside_fraction(conic, cell.triangle, cell.density);
    if (share >= 0.0 || cell.solid_angle >= 1e-4 * reference_solid_angle) return share;
    int inside = 0;
    for (const Vec3& v : cell.triangle.v) inside += contains(conic, v) ? 1 : 0;
    return inside / 3.0;
}

double conic_integral(const TriangleIntegrals& integrals, const SphericalConic& conic, double cell_solid_angle) {
    thread_local std::vector<DirectionCell> queue;
    queue.clear();
    queue.push_back(DirectionCell{});
    double sum = 0.0;
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const DirectionCell cell = queue[head];
        const Overlap relation = cell.label == kHemisphereLabel ? Overlap::partial : overlap(conic, cell.triangle);
        if (relation == Overlap::disjoint) continue;
        if (relation == Overlap::inside) {
            sum += integrals.integral(cell);
            continue;
        }
        if (integrals.uniform(cell) && (cell.solid_angle <= cell_solid_angle || cell.depth >= kMaxTriangleDepth)) {
            const double share = cell_share(conic, cell, cell_solid_angle);
            if (share >= 0.0) {
                sum += share * integrals.integral(cell);
                continue;
            }
        }
        if (cell.depth >= kMaxTriangleDepth) continue;
        for (const DirectionCell& child : split(cell, integrals.density)) queue.push_back(child);
    }
    return sum;
}

namespace {

// Jakob 2014 Algorithm 2: the centroid rule against the vertex rule; where they disagree, the sum
// over the four children, remembered under the triangle's label.
double integrate(TriangleIntegrals& integrals, std::uint64_t label, const SphericalTriangle& t, int depth, int max_depth) {
    const double by_vertices = vertex_rule(integrals.density, t);
    const double by_centre = solid_angle(t) * integrals.density(centre(t));
    const double difference = std::abs(by_centre - by_vertices);
    if (difference < integrals.absolute_tolerance || difference < integrals.relative_tolerance * by_vertices ||
        depth >= max_depth)
        return by_vertices;
    const std::array<SphericalTriangle, 4> children = split(t);
    double sum = 0.0;
    for (int j = 0; j < 4; ++j) sum += integrate(integrals, child_label(label, j + 1), children[j], depth + 1, max_depth);
    integrals.table[label] = sum;
    return sum;
}

}  // namespace

TriangleIntegrals integrate_distribution(NormalDensity density, double relative_tolerance, double absolute_tolerance,
                                         int max_depth) {
    TriangleIntegrals integrals;
    integrals.density = std::move(density);
    integrals.relative_tolerance = relative_tolerance;
    integrals.absolute_tolerance = absolute_tolerance;
    const std::array<SphericalTriangle, 4> quadrants = hemisphere_quadrants();
    for (int j = 0; j < 4; ++j)
        integrate(integrals, child_label(kHemisphereLabel, j + 1), quadrants[j], 1, std::min(max_depth, kMaxTriangleDepth));
    return integrals;
}

}  // namespace glintscope
