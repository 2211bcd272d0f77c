#include "methods/discrete/discrete_lobe.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "normal_density/microfacet_answers.hpp"
#include "normal_density/normal_density.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/fit/ndf_models.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "numerics/disk_table.hpp"

namespace glintscope {
namespace {

constexpr double kMaxTileFlakes = 9e15;  // counts stay exact integers in a double (2^53)

struct SmoothDistribution {
    NormalDensity density;
    SmoothSampler sampler;
    int table_depth = 16;  // Algorithm 2's deepest table level
};

// The Beckmann roughness with the table's mean square slopes along x and y (Beckmann's slope
// variance is α²/2 per axis), over the flakes' share of projected area D dA on the disk.
SmoothSampler beckmann_of_slopes(const DiskTable& table) {
    const int n = table.resolution;
    double mass = 0.0, xx = 0.0, yy = 0.0;
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            const DiskPoint p = disk_pixel_point(row, col, n);
            if (!inside_unit_disk(p)) continue;
            const double w = table.pixel(row, col), z2 = 1.0 - p.x * p.x - p.y * p.y;
            mass += w;
            xx += w * p.x * p.x / z2;
            yy += w * p.y * p.y / z2;
        }
    if (!(mass > 0.0)) return {SmoothSampler::Shape::beckmann, 0.4, 0.4};
    auto alpha = [&](double mean_square) { return std::clamp(std::sqrt(2.0 * mean_square / mass), 0.005, 2.0); };
    return {SmoothSampler::Shape::beckmann, 2.0 * alpha(xx), 2.0 * alpha(yy)};
}

SmoothDistribution smooth_distribution(const LobeQuery& query) {
    const std::string name = method_option_text(query, "distribution", "beckmann");
    const double alpha = method_option_number(query, "alpha", 0.2);
    const double ax = method_option_number(query, "alpha_x", alpha);
    const double ay = method_option_number(query, "alpha_y", alpha);
    for (const double a : {ax, ay})
        if (!(a >= 0.005 && a <= 2.0)) throw Error("option alpha must be between 0.005 and 2, got " + shortest_text(a));
    // Jakob 2014 §3.4: the sampler's roughness α_sample = 2α.
    if (name == "beckmann")
        return {[ax, ay](Vec3 m) { return m.z > 0.0 ? beckmann_ndf(ax, ay, m) * m.z : 0.0; },
                {SmoothSampler::Shape::beckmann, 2.0 * ax, 2.0 * ay}};
    if (name == "ggx")
        return {[ax, ay](Vec3 m) { return m.z > 0.0 ? ggx_ndf(ax, ay, m) * m.z : 0.0; },
                {SmoothSampler::Shape::ggx, 2.0 * ax, 2.0 * ay}};
    if (name == "pndf") {
        // The surface's own exact P-NDF of the footprint, at up to 4× the image's resolution and
        // read bilinearly: glitter with the angular structure of the heightfield's normals.
        auto table = std::make_shared<DiskTable>();
        table->resolution = std::min(4 * query.resolution, 1024);
        table->values = normal_density(*query.surface, query.footprint, table->resolution, NormalDensitySettings{});
        // Below the table's pixel the density is bilinear, which the shares of linear weights
        // follow: the hash table stops at triangles of about a pixel, (π/2)/2^(d−1) ≤ 2/N.
        const int depth = 1 + static_cast<int>(std::ceil(std::log2(0.25 * pi * table->resolution)));
        return {[table](Vec3 m) { return m.z > 0.0 ? table->at(m.x, m.y) * m.z : 0.0; }, beckmann_of_slopes(*table), depth};
    }
    throw Error("option distribution must be beckmann, ggx or pndf, got '" + name + "'");
}

// The default cone: the solid angle of one pixel at the centre of the disk, πγ² = (2/N)².
double default_cone(int resolution) { return 2.0 / (std::sqrt(pi) * resolution); }

FlakeFootprint flake_footprint(const Footprint& footprint) {
    FlakeFootprint flake;
    flake.centre_x = footprint.centre_um.x;
    flake.centre_y = footprint.centre_um.y;
    flake.gaussian = footprint.shape == FootprintShape::gaussian;
    flake.sigma_um = footprint.sigma_um;
    flake.size_um = box_width_um(footprint);
    flake.size_y_um = box_height_um(footprint);
    return flake;
}

}  // namespace

PixelQuery pixel_query(const LobeQuery& query, const DiscreteSetup& setup, DiskPoint p) {
    const double fraction_per_flake = 1.0 / (setup.density_per_um2 * setup.footprint.area_um2());
    PixelQuery pixel;
    if (query.quantity == Quantity::ndf) {
        pixel.h = direction_from_disk(p.x, p.y);
        pixel.conic = spherical_conic(pixel.h, pixel.h, 2.0 * setup.cone);  // the cap of γ about h
        // ∫_cap m_z dω = h_z π sin²γ: the cap's projected area, so that D̂ → D (Jakob 2014 eq. 6).
        const double sine = std::sin(setup.cone);
        pixel.scale = fraction_per_flake / (pixel.h.z * pi * sine * sine);
        return pixel;
    }
    return lobe_pixel_query(setup, query.omega_i, direction_from_disk(p.x, p.y));
}

PixelQuery lobe_pixel_query(const DiscreteSetup& setup, Vec3 omega_i, Vec3 omega_o) {
    const double fraction_per_flake = 1.0 / (setup.density_per_um2 * setup.footprint.area_um2());
    PixelQuery pixel;
    pixel.h = normalize(omega_i + omega_o);
    pixel.conic = spherical_conic(omega_i, omega_o, setup.cone);  // Jakob 2014 eq. 8
    const double cone_solid_angle = 2.0 * pi * (1.0 - std::cos(setup.cone));
    // Jakob 2014 eq. 5 with D̂ the flakes' share of projected area: the 1/h_z turns it into the
    // microfacet lobe F D G/(4 cosθ_i cosθ_o) averaged over the cone as N → ∞ (docs/discrete.md).
    pixel.scale = fraction_per_flake * dot(omega_i, pixel.h) /
                  (cone_solid_angle * pixel.h.z * omega_i.z * omega_o.z);
    return pixel;
}

// F at the first wavelength, for one direction pair (1 without a material).
double fresnel_at(const LobeQuery& query, Vec3 h) {
    if (query.material.name.empty()) return 1.0;
    return fresnel_conductor(complex_refractive_index(query.material.name, query.wavelengths_um[0]), dot(query.omega_i, h));
}

void setup_discrete(const LobeQuery& query, DiscreteSetup& setup) {
    SmoothDistribution smooth = smooth_distribution(query);
    setup.integrals = integrate_distribution(std::move(smooth.density), 1e-2, 1e-8, smooth.table_depth);
    setup.sampler = smooth.sampler;
    setup.footprint = flake_footprint(query.footprint);
    const double tile = method_option_length_um(query, "tile", 1000.0);
    const double reach = setup.footprint.gaussian
                             ? 5.0 * setup.footprint.sigma_um
                             : 0.5 * std::max(setup.footprint.size_um, setup.footprint.size_y_um);
    if (!(tile >= 4.0 * reach && tile <= 1e6))
        throw Error("option tile must be at least four times the footprint's reach (" + shortest_text(4.0 * reach) +
                    " um) and at most 1 m, got " + shortest_text(tile) + " um");
    const bool by_density = query.method_options.contains("flake_density");
    if (by_density && query.method_options.contains("flakes"))
        throw Error("options flakes and flake_density are alternatives: give one");
    const double area = setup.footprint.area_um2();
    setup.density_per_um2 = by_density ? method_option_number(query, "flake_density", 0.0)
                                       : method_option_number(query, "flakes", 1e6) / area;
    const double tile_flakes = std::round(setup.density_per_um2 * tile * tile);
    if (!(tile_flakes >= 1.0 && tile_flakes <= kMaxTileFlakes))
        throw Error("the tile would hold " + shortest_text(tile_flakes) + " flakes: choose flakes (or flake_density) so that "
                    "the tile holds between 1 and 9e15");
    setup.density_per_um2 = tile_flakes / (tile * tile);  // the density the integer count realises
    const double cone_deg = method_option_number(query, "cone", default_cone(query.resolution) * 180.0 / pi);
    if (!(cone_deg >= 1e-4 && cone_deg <= 30.0))
        throw Error("option cone must be between 0.0001 and 30 degrees, got " + shortest_text(cone_deg));
    setup.cone = cone_deg * pi / 180.0;
    setup.epsilon = method_option_number(query, "error", 0.1);
    if (!(setup.epsilon >= 0.0 && setup.epsilon <= 1.0))
        throw Error("option error must be between 0 and 1, got " + shortest_text(setup.epsilon));
    const double seed = method_option_number(query, "seed", 1.0);
    if (!(seed >= 0.0 && seed <= 9e15 && seed == std::floor(seed)))
        throw Error("option seed must be a whole number from 0 to 9e15, got " + shortest_text(seed));
    setup.material.normals = &setup.integrals;
    setup.material.tile_um = tile;
    setup.material.flakes = tile_flakes;
    setup.material.seed = static_cast<std::uint64_t>(seed);
    // Eq. 11's expected query area: the region the footprint's weight reaches (a Gaussian's ±5σ_c
    // square, whose every node the traversal visits; a box itself), not its effective area A_c.
    setup.material.query_area_um2 =
        setup.footprint.gaussian ? 4.0 * reach * reach : setup.footprint.size_um * setup.footprint.size_y_um;
    // Eq. 11's expected solid angle: the set Ω_h at the centre of the image (a cap of γ/2 for a lobe,
    // of γ for an NDF).
    const double cap = query.quantity == Quantity::ndf ? setup.cone : 0.5 * setup.cone;
    setup.material.query_solid_angle = 2.0 * pi * (1.0 - std::cos(cap));
}

namespace {

// The metal's index per wavelength where a lobe has Fresnel's factor; none otherwise.
std::vector<ComplexIndex> lobe_refractive_indices(const LobeQuery& query) {
    std::vector<ComplexIndex> eta;
    if (query.quantity == Quantity::brdf && !query.material.name.empty())
        for (double lambda : query.wavelengths_um) eta.push_back(complex_refractive_index(query.material.name, lambda));
    return eta;
}

struct QueryTotals {
    std::vector<std::vector<double>> sums;  // [layer][pixel]: Σ over sub-pixels
    double nodes = 0.0;
    double queries = 0.0;
};

QueryTotals evaluate_pixels(const LobeQuery& query, const DiscreteSetup& setup) {
    const int n = query.resolution;
    const int k = query.supersample;
    const std::size_t layers = query.wavelengths_um.size();
    const std::vector<ComplexIndex> eta = lobe_refractive_indices(query);
    const bool fresnel = !eta.empty();
    QueryTotals totals;
    totals.sums.assign(layers, std::vector<double>(static_cast<std::size_t>(n) * n, 0.0));
    std::vector<double> row_nodes(n, 0.0), row_queries(n, 0.0);
    parallel_for(static_cast<std::size_t>(n), 1, [&](std::size_t begin, std::size_t end) {
        SplitCache cache;
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < n; ++c) {
                const std::size_t pixel = r * n + c;
                if (!inside_unit_disk(disk_pixel_point(static_cast<int>(r), c, n))) continue;
                for (int a = 0; a < k; ++a)
                    for (int b = 0; b < k; ++b) {
                        const DiskPoint p = disk_subpixel_point(static_cast<int>(r), c, a, b, n, k);
                        if (!inside_unit_disk(p)) continue;
                        const PixelQuery q = pixel_query(query, setup, p);
                        const FlakeCount count = count_flakes(setup.material, setup.footprint, q.conic, setup.epsilon, &cache);
                        row_nodes[r] += static_cast<double>(count.nodes);
                        row_queries[r] += 1.0;
                        const double value = q.scale * count.weighted;
                        for (std::size_t l = 0; l < layers; ++l)
                            totals.sums[l][pixel] += fresnel ? fresnel_conductor(eta[l], dot(query.omega_i, q.h)) * value : value;
                    }
            }
    });
    for (int r = 0; r < n; ++r) {
        totals.nodes += row_nodes[r];
        totals.queries += row_queries[r];
    }
    return totals;
}


LobeImage discrete_lobe(const LobeQuery& query) {
    DiscreteSetup setup;
    setup_discrete(query, setup);
    const QueryTotals totals = evaluate_pixels(query, setup);
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um, query.quantity);
    for (std::size_t l = 0; l < totals.sums.size(); ++l) store_subpixel_means(image, l, totals.sums[l], query.supersample);
    Provenance& m = image.metadata;
    m["discrete.flakes_in_footprint"] = shortest_text(setup.density_per_um2 * setup.footprint.area_um2());
    m["discrete.flakes_in_tile"] = shortest_text(setup.material.flakes);
    m["discrete.flake_density_per_um2"] = shortest_text(setup.density_per_um2);
    m["discrete.distribution"] = method_option_text(query, "distribution", "beckmann");
    if (m["discrete.distribution"] != "pndf")  // said once by the pipeline's notes
        m["note.discrete"] = "discrete: the flake normals follow the " + m["discrete.distribution"] +
                             " distribution of option alpha (default 0.2), not the heightfield (option "
                             "distribution=pndf uses its normals)";
    m["discrete.cone_deg"] = shortest_text(setup.cone * 180.0 / pi);
    m["discrete.seed"] = std::to_string(setup.material.seed);
    m["discrete.tile_um"] = shortest_text(setup.material.tile_um);
    m["discrete.error"] = shortest_text(setup.epsilon);
    m["discrete.table_entries"] = std::to_string(setup.integrals.table.size());
    m["discrete.nodes_per_query"] = shortest_text(totals.queries > 0.0 ? std::round(totals.nodes / totals.queries) : 0.0);
    return image;
}

// f_r(ω_i, ω_o) of the flakes in `flakes`: those reflecting ω_i into the cone of γ about ω_o
// (Jakob 2014 eq. 8, counted by Algorithm 1), by eq. 5 with that footprint's area (pixel
// queries' scale is per the setup's footprint area, hence the ratio), F per wavelength.
std::function<std::vector<double>(Vec3, Vec3)> counting_eval(std::shared_ptr<const DiscreteSetup> setup,
                                                            std::vector<ComplexIndex> indices, std::size_t layers,
                                                            FlakeFootprint flakes) {
    const double area_ratio = setup->footprint.area_um2() / flakes.area_um2();
    return [setup, indices, layers, flakes, area_ratio](Vec3 omega_i, Vec3 omega_o) {
        const PixelQuery pixel = lobe_pixel_query(*setup, omega_i, omega_o);
        const FlakeCount count = count_flakes(setup->material, flakes, pixel.conic, setup->epsilon);
        std::vector<double> f(layers, pixel.scale * area_ratio * count.weighted);
        for (std::size_t l = 0; l < indices.size(); ++l) f[l] *= fresnel_conductor(indices[l], dot(omega_i, pixel.h));
        return f;
    };
}

// The BRDF of one footprint for single directions: eval is the image's pixel at ω_o, and the
// sampler is Jakob 2014 §3.4's (flake_sampling.hpp).
PointAnswers discrete_point(const LobeQuery& query) {
    auto setup = std::make_shared<DiscreteSetup>();  // shared, so material.normals stays valid
    setup_discrete(query, *setup);
    auto sampler = std::make_shared<const FlakeSampler>(setup->sampler, setup->cone);
    PointAnswers answers;
    answers.eval = counting_eval(setup, lobe_refractive_indices(query), query.wavelengths_um.size(), setup->footprint);
    answers.sample = [sampler](Vec3 omega_i, double u1, double u2) { return sampler->sample(omega_i, u1, u2); };
    answers.pdf = [sampler](Vec3 omega_i, Vec3 omega_o) { return sampler->pdf(omega_i, omega_o); };
    return answers;
}

// Jakob 2014's query for any footprint of a renderer's shading points: the flakes weighted by the
// footprint's Gaussian (σ = σ_c). The flakes themselves (tile, density, eq. 11's split sizes) are
// fixed once by the query's own footprint, so every footprint sees the same flakes.
// distribution=pndf is the P-NDF of the query's footprint alone, and a box or the whole field
// is not a Gaussian: those are answered from the images.
PointAnswersAt discrete_point_field(const LobeQuery& query) {
    auto setup = std::make_shared<DiscreteSetup>();  // its material points into its own integrals: never moved
    setup_discrete(query, *setup);
    if (method_option_text(query, "distribution", "beckmann") == "pndf" || query.quantity != Quantity::brdf)
        return [](const Footprint&) { return PointAnswers{}; };
    const std::size_t layers = query.wavelengths_um.size();
    const std::vector<ComplexIndex> indices = lobe_refractive_indices(query);
    return [setup, layers, indices](const Footprint& footprint) -> PointAnswers {
        if (footprint.shape != FootprintShape::gaussian) return {};
        PointAnswers answers;
        answers.eval = counting_eval(setup, indices, layers, flake_footprint(footprint));
        return answers;
    };
}

}  // namespace

MethodEntry discrete_method() {
    MethodEntry entry;
    entry.info.name = "discrete";
    entry.info.description = "discrete stochastic microfacets: N glittering flakes counted per pixel cone";
    entry.info.reference = "Jakob 2014 eq. 5-10";
    entry.info.quantities = {Quantity::brdf, Quantity::ndf};
    entry.info.ignored = {QueryField::model};
    entry.info.options = {
        {"flakes", "flakes in the footprint (box area, or A_c = pi sigma_c^2 for a Gaussian) (default 1e6)"},
        {"flake_density", "flakes per um^2, instead of flakes"},
        {"distribution", "beckmann, ggx, or pndf (the heightfield's own P-NDF of the footprint): the smooth "
                         "distribution of flake normals (default beckmann)"},
        {"alpha", "roughness of beckmann or ggx (default 0.2)"},
        {"alpha_x", "roughness along x (default alpha)"},
        {"alpha_y", "roughness along y (default alpha)"},
        {"cone", "degrees: half-angle of each pixel's cone of directions, omega_o for brdf, h for ndf "
                 "(default: one centre pixel's solid angle)"},
        {"seed", "which flakes: a whole number (default 1)"},
        {"tile", "side of the periodic square of flakes (default 1000um)"},
        {"error", "relative error allowed where the count is estimated, eq. 10 (default 0.1)"},
    };
    entry.compute = discrete_lobe;
    entry.point = discrete_point;
    entry.point_field = discrete_point_field;
    return entry;
}

}  // namespace glintscope
