#include "methods/discrete/flake_hierarchy.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/counter_rng.hpp"
#include "glintscope/core/error.hpp"

namespace glintscope {

double FlakeFootprint::area_um2() const { return gaussian ? pi * sigma_um * sigma_um : size_um * size_y_um; }

FlakeNode root_node(const FlakeMaterial& material) {
    FlakeNode root;
    root.size = material.tile_um;
    root.count = material.flakes;
    root.label = 1;
    return root;
}

double binomial_draw(double n, double q, std::uint64_t seed, std::uint64_t label, int index) {
    if (n <= 0.0 || q <= 0.0) return 0.0;
    if (q >= 1.0) return n;
    if (q > 0.5) return n - binomial_draw(n, 1.0 - q, seed, label, index);
    const CounterRng rng(seed, label);
    const double variance = n * q * (1.0 - q);
    if (variance >= 50.0) {
        double z = 0.0, unused = 0.0;
        rng.normal_pair(static_cast<std::uint64_t>(index), z, unused);
        return std::clamp(std::round(n * q + z * std::sqrt(variance)), 0.0, n);
    }
    // Inversion: P(k + 1)/P(k) = (n − k)/(k + 1) · q/(1 − q), from P(0) = (1 − q)^n ≥ e^−200 here.
    const double u = rng.uniform(1000 + static_cast<std::uint64_t>(index));
    double probability = std::exp(n * std::log1p(-q));
    double cumulative = probability;
    double k = 0.0;
    const double odds = q / (1.0 - q);
    while (u > cumulative && k < n) {
        probability *= (n - k) / (k + 1.0) * odds;
        k += 1.0;
        cumulative += probability;
        if (probability == 0.0 && k > n * q) break;  // the tail beyond double precision
    }
    return k;
}

namespace {

constexpr int kMaxSpaceDepth = 40;

std::uint64_t node_child_label(std::uint64_t parent, int j) {
    return CounterRng(parent, static_cast<std::uint64_t>(j) + 1).bits(0);
}

// The multinomial draw of Jakob 2014 §3.4 as conditional binomials: child j gets
// Binomial(remaining, p_j / (p_j + … + p_4)), so the four counts always sum to n.
std::array<double, 4> multinomial_draw(double n, const std::array<double, 4>& p, std::uint64_t seed, std::uint64_t label) {
    std::array<double, 4> counts{};
    double remaining = n;
    double rest = p[0] + p[1] + p[2] + p[3];
    for (int j = 0; j < 3; ++j) {
        const double q = rest > 0.0 ? std::clamp(p[j] / rest, 0.0, 1.0) : 0.0;
        counts[j] = binomial_draw(remaining, q, seed, label, j);
        remaining -= counts[j];
        rest -= p[j];
    }
    counts[3] = remaining;
    return counts;
}

// Jakob 2014 eq. 11: split in space when the node is larger, relative to the expected query, in
// space than in direction.
bool split_in_space(const FlakeMaterial& material, const FlakeNode& node) {
    if (node.direction.depth >= kMaxTriangleDepth) return true;
    if (node.space_depth >= kMaxSpaceDepth) return false;
    return material.query_area_um2 / (node.size * node.size) < material.query_solid_angle / node.direction.solid_angle;
}

}  // namespace

std::array<FlakeNode, 4> split(const FlakeMaterial& material, const FlakeNode& node) {
    std::array<FlakeNode, 4> children;
    std::array<double, 4> p{0.25, 0.25, 0.25, 0.25};
    if (split_in_space(material, node)) {
        const double half = 0.5 * node.size;
        for (int j = 0; j < 4; ++j) {
            FlakeNode& child = children[j];
            child = node;
            child.x0 = node.x0 + (j % 2) * half;
            child.y0 = node.y0 + (j / 2) * half;
            child.size = half;
            child.space_depth = node.space_depth + 1;
        }
    } else {
        const std::array<DirectionCell, 4> cells = split(node.direction, material.normals->density);
        for (int j = 0; j < 4; ++j) {
            children[j] = node;
            children[j].direction = cells[j];
            p[j] = material.normals->integral(cells[j]);
        }
    }
    const std::array<double, 4> counts = multinomial_draw(node.count, p, material.seed, node.label);
    for (int j = 0; j < 4; ++j) {
        children[j].count = counts[j];
        children[j].label = node_child_label(node.label, j);
    }
    return children;
}

namespace {

// The footprint's weight over a node's square: whether it is zero there, whether it is the box's
// full weight 1 everywhere, and its mean and mean square over the square.
struct SpatialShare {
    bool disjoint = false;
    bool inside = false;
    double mean = 0.0;
    double mean_square = 0.0;
};

struct AxisShare {
    bool overlaps = false;
    bool inside = false;
    double mean = 0.0;
    double mean_square = 0.0;
};

// ∫_a^b exp(−(t − c)²/σ²) dt / (b − a), with erfc on the far side of the centre so that tails
// keep their relative precision.
double gaussian_mean(double a, double b, double c, double sigma) {
    const double u = (a - c) / sigma, v = (b - c) / sigma;
    const double difference = u >= 0.0 ? std::erfc(u) - std::erfc(v)
                              : v <= 0.0 ? std::erfc(-v) - std::erfc(-u)
                                         : std::erf(v) - std::erf(u);
    return 0.5 * std::sqrt(pi) * sigma * difference / (b - a);
}

constexpr double kGaussianCut = 5.0;  // in σ: exp(−25) ≈ 1.4e-11

AxisShare axis_share(double a, double size, double centre, double side, const FlakeFootprint& footprint, double tile) {
    AxisShare share;
    const double b = a + size;
    for (int image = -1; image <= 1; ++image) {
        const double c = centre + image * tile;
        if (footprint.gaussian) {
            if (b <= c - kGaussianCut * footprint.sigma_um || a >= c + kGaussianCut * footprint.sigma_um) continue;
            share.overlaps = true;
            share.mean += gaussian_mean(a, b, c, footprint.sigma_um);
            share.mean_square += gaussian_mean(a, b, c, footprint.sigma_um / std::sqrt(2.0));
        } else {
            const double low = c - 0.5 * side, high = c + 0.5 * side;
            const double length = std::min(b, high) - std::max(a, low);
            if (length <= 0.0) continue;
            share.overlaps = true;
            share.inside = share.inside || (a >= low && b <= high);
            share.mean += length / size;
        }
    }
    if (share.inside) share.mean = 1.0;
    if (!footprint.gaussian) share.mean_square = share.mean;
    return share;
}

SpatialShare spatial_share(const FlakeNode& node, const FlakeFootprint& footprint, double tile) {
    const AxisShare x = axis_share(node.x0, node.size, footprint.centre_x, footprint.size_um, footprint, tile);
    const AxisShare y = axis_share(node.y0, node.size, footprint.centre_y, footprint.size_y_um, footprint, tile);
    SpatialShare share;
    share.disjoint = !(x.overlaps && y.overlaps);
    share.inside = x.inside && y.inside;
    share.mean = x.mean * y.mean;
    share.mean_square = x.mean_square * y.mean_square;
    return share;
}

// The weight of a flake at (x, y): the footprint's, at the nearest periodic image of its centre.
double flake_weight(const FlakeFootprint& footprint, double tile, double x, double y) {
    const auto offset = [tile](double d) { return d - tile * std::round(d / tile); };
    const double dx = offset(x - footprint.centre_x), dy = offset(y - footprint.centre_y);
    if (!footprint.gaussian)
        return std::abs(dx) <= 0.5 * footprint.size_um && std::abs(dy) <= 0.5 * footprint.size_y_um ? 1.0 : 0.0;
    const double cut = kGaussianCut * footprint.sigma_um;
    if (std::abs(dx) >= cut || std::abs(dy) >= cut) return 0.0;
    return std::exp(-(dx * dx + dy * dy) / (footprint.sigma_um * footprint.sigma_um));
}

// Whether one flake's normal, D-distributed in `cell`, lies in the conic: its normal is the end
// of an endless path down the triangle tree, a categorical draw per level from the flake's own
// stream, followed only until the cell is wholly inside or outside the conic.
bool flake_reflects(const FlakeMaterial& material, DirectionCell cell, const SphericalConic& conic, const CounterRng& rng) {
    for (std::uint64_t level = 0;; ++level) {
        const Overlap relation = cell.label == kHemisphereLabel ? Overlap::partial : overlap(conic, cell.triangle);
        if (relation != Overlap::partial) return relation == Overlap::inside;
        if (cell.depth >= kMaxTriangleDepth) return contains(conic, centre(cell.triangle));
        const std::array<DirectionCell, 4> children = split(cell, material.normals->density);
        std::array<double, 4> cumulative{};
        double total = 0.0;
        for (int j = 0; j < 4; ++j) cumulative[j] = total += material.normals->integral(children[j]);
        const double u = rng.uniform(2 + level) * total;
        int j = 0;
        while (j < 3 && u > cumulative[j]) ++j;
        cell = children[j];
    }
}

// A leaf's flakes, each drawn from its own stream: a position uniform in the square and a normal
// from D in the triangle (given the count, the flakes of a node are independent and so
// distributed), the weight exact.
double leaf_count(const FlakeMaterial& material, const FlakeFootprint& footprint, const SphericalConic& conic,
                  const FlakeNode& leaf) {
    double weighted = 0.0;
    for (int k = 0; k < static_cast<int>(leaf.count); ++k) {
        const CounterRng rng(material.seed, node_child_label(leaf.label, 4 + k));
        const double weight =
            flake_weight(footprint, material.tile_um, leaf.x0 + leaf.size * rng.uniform(0), leaf.y0 + leaf.size * rng.uniform(1));
        if (weight > 0.0 && flake_reflects(material, leaf.direction, conic, rng)) weighted += weight;
    }
    return weighted;
}

// Where eq. 10 stops, Jakob 2014 adds the node's expected share n·p. That keeps the mean but not
// the spread: at tens of flakes per pixel a tenth of the glitter's contrast would be lost. We draw
// the share instead as c·Binomial(n, π) with the mean m·p and the variance n(q·p − m²p²) of the
// flakes' weighted count (m, q: the footprint weight's mean and mean square over the node):
// c = q/m, π = m²p/q; for a box (q = m) exactly Binomial(n, m·p). The draw is seeded by the node
// and the query: seeded by the node alone, every pixel whose cone a node serves would deviate
// alike and the lobe would show the node's triangle.
double estimated_share(const FlakeMaterial& material, const FlakeNode& node, const SpatialShare& space, double p,
                       std::uint64_t query_key) {
    if (space.mean <= 0.0 || p <= 0.0) return 0.0;
    const double scale = space.mean_square / space.mean;
    const std::uint64_t label = CounterRng(node.label, query_key).bits(0);
    return scale * binomial_draw(node.count, std::min(1.0, space.mean * p / scale), material.seed, label, 3);
}

// A key for the query: its directions and footprint centre rounded to 2^−30 (1e-9), so that the
// same directions computed along another path (a BSDF's eval normalises the caller's unit vectors
// again, an image derives them from its pixels) draw the same estimates: a difference of one ulp
// changes the key only where it crosses a rounding boundary, about once in 10⁷ queries.
std::uint64_t query_key(const SphericalConic& conic, const FlakeFootprint& footprint) {
    std::uint64_t key = 0;
    for (const double value : {conic.axis.x, conic.axis.y, conic.axis.z, conic.facing.x, conic.facing.y, conic.facing.z,
                               conic.c[0][0], footprint.centre_x, footprint.centre_y})
        key = CounterRng(key, static_cast<std::uint64_t>(std::llround(std::ldexp(value, 30)))).bits(0);
    return key;
}

constexpr std::size_t kCacheEntries = 1 << 16;
constexpr std::size_t kMaxQueue = 1 << 20;  // 200 MB of pending nodes

std::array<FlakeNode, 4> cached_split(const FlakeMaterial& material, const FlakeNode& node, SplitCache* cache) {
    if (cache == nullptr) return split(material, node);
    const auto found = cache->children.find(node.label);
    if (found != cache->children.end()) return found->second;
    if (cache->children.size() >= kCacheEntries) cache->children.clear();
    return cache->children.emplace(node.label, split(material, node)).first->second;
}

}  // namespace

FlakeCount count_flakes(const FlakeMaterial& material, const FlakeFootprint& raw_footprint, const SphericalConic& conic,
                        double epsilon, SplitCache* cache) {
    FlakeFootprint footprint = raw_footprint;
    footprint.centre_x -= material.tile_um * std::floor(footprint.centre_x / material.tile_um);
    footprint.centre_y -= material.tile_um * std::floor(footprint.centre_y / material.tile_um);
    struct Pending {
        FlakeNode node;
        SpatialShare space;  // of the node's square: a directional split keeps it
    };
    thread_local std::vector<Pending> queue;
    queue.clear();
    const FlakeNode root = root_node(material);
    queue.push_back({root, spatial_share(root, footprint, material.tile_um)});
    FlakeCount result;
    // Eq. 10 compares a node's error with the running count, a stand-in for the query's total that
    // is 0 until something is counted; half the expected total is a floor for it that lets the first
    // nodes stop too (the realised total falls below half its mean with negligible probability once
    // the mean exceeds a few flakes, and below that nothing is estimated anyway).
    const double expected = material.flakes / (material.tile_um * material.tile_um) * footprint.area_um2() *
                            conic_integral(*material.normals, conic, material.query_solid_angle);
    const double floor = 0.5 * expected;
    const std::uint64_t key = query_key(conic, footprint);
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const FlakeNode node = queue[head].node;
        const SpatialShare space = queue[head].space;
        ++result.nodes;
        const bool hemisphere = node.direction.label == kHemisphereLabel;
        const Overlap direction = hemisphere ? Overlap::partial : overlap(conic, node.direction.triangle);
        if (direction == Overlap::disjoint) continue;
        if (space.inside && direction == Overlap::inside) {
            result.weighted += node.count;  // Algorithm 1 line 10
            continue;
        }
        if (node.count <= kLeafFlakes) {
            result.weighted += leaf_count(material, footprint, conic, node);
            continue;
        }
        // Algorithm 1 lines 11-13: an estimated share (estimated_share), where D is uniform in the
        // node (or the triangle lies wholly inside the conic) and the share's spread is below ε of
        // max(running count, half the expected total) plus the node's own expected share.
        double p = -1.0;
        if (direction == Overlap::inside) p = 1.0;
        else if (material.normals->uniform(node.direction)) p = cell_share(conic, node.direction, material.query_solid_angle);
        const double n = node.count;
        const bool at_floor = node.space_depth >= kMaxSpaceDepth && node.direction.depth >= kMaxTriangleDepth;
        if (p >= 0.0) {
            const double mean = n * space.mean * p;
            const double variance = n * (space.mean_square * p - space.mean * space.mean * p * p);
            if (std::sqrt(std::max(variance, 0.0)) < epsilon * (std::max(result.weighted, floor) + mean) || at_floor) {
                result.weighted += estimated_share(material, node, space, p, key);
                continue;
            }
        } else if (at_floor) {
            int inside_vertices = 0;
            for (const Vec3& v : node.direction.triangle.v) inside_vertices += contains(conic, v) ? 1 : 0;
            result.weighted += n * space.mean * inside_vertices / 3.0;
            continue;
        }
        if (queue.size() > kMaxQueue)
            throw Error("a query needed more than " + std::to_string(kMaxQueue) +
                        " nodes of the flake hierarchy: raise option error or use fewer flakes");
        const std::array<FlakeNode, 4> children = cached_split(material, node, cache);
        const bool spatial = children[0].size != node.size;
        for (const FlakeNode& child : children) {
            if (child.count <= 0.0) continue;
            const SpatialShare share = spatial ? spatial_share(child, footprint, material.tile_um) : space;
            if (!share.disjoint) queue.push_back({child, share});
        }
    }
    return result;
}

}  // namespace glintscope
