#include "methods/geometric/geometric_lobe.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "normal_density/microfacet_answers.hpp"
#include "normal_density/normal_density.hpp"
#include "numerics/disk_table.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/fit/ndf_fit.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "methods/filtered/filtered_ndf.hpp"
#include "methods/pndf/pndf.hpp"

namespace glintscope {
namespace {

enum class Shadowing { none, smith, ellipsoid };

struct GeometricSettings {
    bool filtered = false;
    Shadowing shadowing = Shadowing::none;
    int ndf_oversampling = 4;
    double filter_sigma_um = 1.0;
    NormalDensitySettings density;
};

GeometricSettings read_settings(const LobeQuery& query) {
    GeometricSettings settings;
    settings.density = normal_density_settings(query);
    const std::string ndf = method_option_text(query, "ndf", "pndf");
    if (ndf != "pndf" && ndf != "filtered") throw Error("option ndf must be pndf or filtered, got '" + ndf + "'");
    settings.filtered = ndf == "filtered";
    const std::string shadowing = method_option_text(query, "shadowing", "none");
    if (shadowing == "smith") settings.shadowing = Shadowing::smith;
    else if (shadowing == "ellipsoid") settings.shadowing = Shadowing::ellipsoid;
    else if (shadowing != "none")
        throw Error("option shadowing must be none, smith or ellipsoid, got '" + shadowing + "'");
    settings.ndf_oversampling = method_option_integer(query, "ndf_oversampling", settings.ndf_oversampling, 1, 4);
    settings.filter_sigma_um = filter_sigma_um(query);
    return settings;
}

DiskTable density_table(const LobeQuery& query, const GeometricSettings& settings) {
    DiskTable table;
    table.resolution = std::min(query.resolution * settings.ndf_oversampling, 8192);
    // The tolerance is in lobe pixels: the lobe, not the finer internal table, is what must not move.
    NormalDensitySettings density = settings.density;
    density.tolerance_pixels *= static_cast<double>(table.resolution) / query.resolution;
    if (settings.filtered) {
        const BicubicInterpolant smoothed(gaussian_smoothed(*query.field, settings.filter_sigma_um));
        table.values = normal_density(smoothed, query.footprint, table.resolution, density);
    } else {
        table.values = normal_density(*query.surface, query.footprint, table.resolution, density);
    }
    return table;
}

// Smith's G1 for the tabulated NDF (see the header), on a coarse disk grid of directions read
// bilinearly: Λ varies slowly with direction, and the table keeps the cost independent of N.
constexpr int kSmithDirections = 64;
constexpr int kSmithNormals = 128;

// The NDF summed down to at most `limit`² pixels, as pixel masses (masses add, so Σ D dA is kept).
DiskTable coarse_masses(const DiskTable& density, int limit) {
    const int factor = std::max(1, density.resolution / limit);
    DiskTable coarse;
    coarse.resolution = density.resolution / factor;
    coarse.values.assign(static_cast<std::size_t>(coarse.resolution) * coarse.resolution, 0.0);
    const double fine_area = disk_pixel_area(density.resolution);
    for (int r = 0; r < coarse.resolution * factor; ++r)
        for (int c = 0; c < coarse.resolution * factor; ++c)
            coarse.values[static_cast<std::size_t>(r / factor) * coarse.resolution + c / factor] +=
                density.pixel(r, c) * fine_area;
    return coarse;
}

DiskTable smith_table(const DiskTable& density) {
    const DiskTable masses = coarse_masses(density, kSmithNormals);
    const int coarse = masses.resolution;
    const std::vector<double>& mass = masses.values;
    DiskTable g1;
    g1.resolution = kSmithDirections;
    g1.extend_edges = true;
    g1.values.assign(kSmithDirections * kSmithDirections, 1.0);
    parallel_for(kSmithDirections, 4, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < kSmithDirections; ++c) {
                DiskPoint p = disk_pixel_point(static_cast<int>(r), c, kSmithDirections);
                const double radius = std::hypot(p.x, p.y);
                if (radius > 0.999) p = {p.x * 0.999 / radius, p.y * 0.999 / radius};  // rim pixels read their edge
                const Vec3 omega = direction_from_disk(p.x, p.y);
                double projected = 0.0;  // ∫ D(m) ⟨ω·m⟩⁺ dω_m = Σ mass ⟨ω·m⟩⁺ / m_z
                for (int i = 0; i < coarse; ++i)
                    for (int j = 0; j < coarse; ++j) {
                        const double w = mass[static_cast<std::size_t>(i) * coarse + j];
                        if (w == 0.0) continue;
                        const DiskPoint q = disk_pixel_point(i, j, coarse);
                        if (q.x * q.x + q.y * q.y >= 1.0) continue;
                        const Vec3 m = direction_from_disk(q.x, q.y);
                        projected += w * std::max(0.0, dot(omega, m)) / m.z;
                    }
                g1.values[r * kSmithDirections + c] = projected > 0.0 ? std::min(1.0, omega.z / projected) : 0.0;
            }
    });
    return g1;
}

// Dong 2015 §8: the ellipsoid NDF fitted to the tabulated one (at most 256², where the fit takes
// well under a second), for its closed-form shadowing-masking (eq. 13-14).
NdfFit ellipsoid_fit(const DiskTable& density) {
    const DiskTable masses = coarse_masses(density, 256);
    LobeImage image = make_lobe_image(masses.resolution, {0.5}, Quantity::ndf);
    const double area = disk_pixel_area(masses.resolution);
    for (std::size_t k = 0; k < masses.values.size(); ++k) image.values[k] = static_cast<float>(masses.values[k] / area);
    return fit_ndf(image, NdfModelKind::ellipsoid);
}

// What a footprint's lobe needs, computed once: the NDF table and the shadowing's own tables.
struct GeometricFootprint {
    GeometricSettings settings;
    DiskTable density;
    DiskTable smith_g1;  // Smith only
    NdfFit ellipsoid;    // ellipsoid only
};

GeometricFootprint geometric_footprint(const LobeQuery& query) {
    GeometricFootprint footprint;
    footprint.settings = read_settings(query);
    footprint.density = density_table(query, footprint.settings);
    if (footprint.settings.shadowing == Shadowing::smith) footprint.smith_g1 = smith_table(footprint.density);
    if (footprint.settings.shadowing == Shadowing::ellipsoid) footprint.ellipsoid = ellipsoid_fit(footprint.density);
    return footprint;
}

double shadowing_masking(const GeometricFootprint& footprint, Vec3 omega_i, Vec3 omega_o, Vec3 h) {
    switch (footprint.settings.shadowing) {
        case Shadowing::none: return 1.0;
        case Shadowing::smith:
            return footprint.smith_g1.at(omega_i.x, omega_i.y) * footprint.smith_g1.at(omega_o.x, omega_o.y);
        case Shadowing::ellipsoid:
            return ellipsoid_shadowing_masking(footprint.ellipsoid.model.parameters, omega_i, omega_o, h);  // Dong 2015 eq. 13
    }
    return 1.0;
}

std::vector<ComplexIndex> refractive_indices(const LobeQuery& query) {
    std::vector<ComplexIndex> indices;
    if (!query.material.name.empty())
        for (double lambda : query.wavelengths_um) indices.push_back(complex_refractive_index(query.material.name, lambda));
    return indices;
}

// The image is the point answers' eval at every sub-pixel, so the two agree by construction.
LobeImage geometric_lobe(const LobeQuery& query) {
    const GeometricFootprint footprint = geometric_footprint(query);
    const GeometricSettings& settings = footprint.settings;
    const std::vector<ComplexIndex> indices = refractive_indices(query);
    const Vec3 omega_i = query.omega_i;
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    for (std::size_t l = 0; l < query.wavelengths_um.size(); ++l)
        fill_by_direction(image, l, query.supersample, [&](DiskPoint p) {
            const Vec3 omega_o = direction_from_disk(p.x, p.y);
            const Vec3 h = normalize(omega_i + omega_o);
            const double fresnel = indices.empty() ? 1.0 : fresnel_conductor(indices[l], dot(omega_i, h));
            return fresnel * footprint.density.at(h.x, h.y) * shadowing_masking(footprint, omega_i, omega_o, h) /
                   (4.0 * omega_i.z * omega_o.z);  // Dong 2015 eq. 1
        });
    image.metadata["geometric.ndf"] = settings.filtered ? "filtered" : "pndf";
    image.metadata["geometric.shadowing"] = method_option_text(query, "shadowing", "none");
    if (settings.shadowing == Shadowing::ellipsoid) {
        const EllipsoidNdf& e = footprint.ellipsoid.model.parameters;
        image.metadata["geometric.ellipsoid"] = join_numbers({e.alpha_x, e.alpha_y, e.theta_x, e.theta_y, e.theta_z});
        image.metadata["geometric.ellipsoid_relative_error"] = shortest_text(footprint.ellipsoid.relative_error);
    }
    image.metadata["geometric.ndf_resolution"] = std::to_string(footprint.density.resolution);
    image.metadata["geometric.refinement"] = std::to_string(settings.density.refinement);
    if (settings.filtered) image.metadata["geometric.filter_sigma_um"] = shortest_text(settings.filter_sigma_um);
    return image;
}

PointAnswers geometric_point(const LobeQuery& query) {
    auto footprint = std::make_shared<const GeometricFootprint>(geometric_footprint(query));
    MicrofacetTable table{footprint->density, refractive_indices(query), {}};
    if (footprint->settings.shadowing != Shadowing::none)
        table.shadowing = [footprint](Vec3 i, Vec3 o, Vec3 h) { return shadowing_masking(*footprint, i, o, h); };
    return microfacet_answers(std::move(table), query.wavelengths_um.size());
}

}  // namespace

MethodEntry geometric_method() {
    MethodEntry entry;
    entry.info.name = "geometric";
    entry.info.description = "microfacet lobe F D G / (4 cos cos) with D the exact P-NDF or the filtered NDF";
    entry.info.reference = "Dong 2015 eq. 1";
    entry.info.quantities = {Quantity::brdf};
    entry.info.ignored = {QueryField::model};
    entry.info.options = {{"ndf", "pndf or filtered (default pndf)"},
                          {"shadowing", "none, smith (Smith G1(i) G1(o) of the measured NDF) or ellipsoid (Dong 2015 eq. 13-14 "
                                        "of the ellipsoid fitted to it) (default none)"},
                          {"ndf_oversampling", "internal NDF resolution per lobe pixel, 1-4 (default 4)"},
                          {"filter_sigma", "plane-fit window sigma_f of the filtered NDF, a length (default 1um)"}};
    for (const MethodOption& option : normal_density_options()) entry.info.options.push_back(option);
    entry.info.whole_field = true;
    entry.compute = geometric_lobe;
    entry.point = geometric_point;
    return entry;
}

}  // namespace glintscope
