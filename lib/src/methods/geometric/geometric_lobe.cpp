#include "methods/geometric/geometric_lobe.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <memory>
#include <utility>
#include <optional>

#include "normal_density/microfacet_answers.hpp"
#include "normal_density/normal_bounds_tree.hpp"
#include "normal_density/normal_density.hpp"
#include "numerics/disk_table.hpp"
#include "numerics/small_polygon.hpp"
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

// The internal NDF resolution for point-sampled pixels: ndf_oversampling × the lobe's.
int table_resolution(const LobeQuery& query, const GeometricSettings& settings) {
    return std::min(query.resolution * settings.ndf_oversampling, 8192);
}

// The density settings at an internal resolution: the tolerance is in lobe pixels (the lobe,
// not the finer internal table, is what must not move).
NormalDensitySettings table_density_settings(const LobeQuery& query, const GeometricSettings& settings, int resolution) {
    NormalDensitySettings density = settings.density;
    density.tolerance_pixels *= static_cast<double>(resolution) / query.resolution;
    return density;
}

// The field whose normals D counts: the heightfield's interpolant, or the filtered NDF's
// smoothed one (Dong 2015 §5.1).
std::shared_ptr<const BicubicInterpolant> ndf_surface(const LobeQuery& query, const GeometricSettings& settings) {
    if (!settings.filtered) return query.surface;
    return std::make_shared<const BicubicInterpolant>(gaussian_smoothed(*query.field, settings.filter_sigma_um));
}

DiskTable density_table(const LobeQuery& query, const GeometricSettings& settings) {
    DiskTable table;
    table.resolution = table_resolution(query, settings);
    if (query.supersample == kExactPixels) {
        // A table cell's albedo factor (ω_i·h)/h_z is taken at its centre, wherever in the cell its
        // mass lies: off by up to tanθ_i/N_table relatively (a mirror's single normal). 200 tanθ_i
        // cells across keep that within 0.5% (80°: 1134).
        const double tan_i = std::sqrt(std::max(0.0, 1.0 - query.omega_i.z * query.omega_i.z)) / query.omega_i.z;
        table.resolution = std::min(std::max(table.resolution, int(std::ceil(200.0 * tan_i))), 8192);
    }
    const NormalDensitySettings density = table_density_settings(query, settings, table.resolution);
    table.values = normal_density(*ndf_surface(query, settings), query.footprint, table.resolution, density);
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

// Adds `mass` spread uniformly over a quadrilateral (in pixel units: x along columns, y along
// rows) to the pixels it overlaps, each by its exact share of the quadrilateral's area.
void deposit_polygon(const SmallPolygon& polygon, double mass, int resolution, std::vector<double>& masses) {
    double low_x = INFINITY, high_x = -INFINITY, low_y = INFINITY, high_y = -INFINITY;
    for (int i = 0; i < polygon.count; ++i) {
        low_x = std::min(low_x, polygon.corners[i].x), high_x = std::max(high_x, polygon.corners[i].x);
        low_y = std::min(low_y, polygon.corners[i].y), high_y = std::max(high_y, polygon.corners[i].y);
    }
    const int c0 = std::clamp(int(std::floor(low_x)), 0, resolution - 1), c1 = std::clamp(int(std::floor(high_x)), 0, resolution - 1);
    const int r0 = std::clamp(int(std::floor(low_y)), 0, resolution - 1), r1 = std::clamp(int(std::floor(high_y)), 0, resolution - 1);
    const double area = polygon_area(polygon);
    if ((c0 == c1 && r0 == r1) || !(area > 0.0)) {  // within one pixel (or degenerate): all of it there
        masses[static_cast<std::size_t>(r0) * resolution + c0] += mass;
        return;
    }
    for (int r = r0; r <= r1; ++r) {
        const SmallPolygon row = clip_polygon(clip_polygon(polygon, false, r, false), false, r + 1, true);
        if (row.count < 3) continue;
        for (int c = c0; c <= c1; ++c) {
            const SmallPolygon piece = clip_polygon(clip_polygon(row, true, c, false), true, c + 1, true);
            if (piece.count >= 3) masses[static_cast<std::size_t>(r) * resolution + c] += mass * polygon_area(piece) / area;
        }
    }
}

// The lobe integrated over its pixels exactly (supersample exact, the default), for the
// piecewise-constant NDF table: by Dong 2015
// eq. 1 with dω_o = 4 (ω_i·h) dω_h and dA_h = h_z dω_h, a table cell of density D and disk area
// A carries albedo F D G (ω_i·h)/(cosθ_i h_z)·A, reflected into the image of the cell under
// h ↦ ω_o = 2(ω_i·h)h − ω_i; that image (its corners' quadrilateral) is spread over the lobe's
// pixels by exact area shares. A lobe narrower than a pixel (a mirror's) keeps its energy at any
// resolution, which point samples of D would miss or double. `value(h, ω_o, cell)` gives
// F·G for the cell's centre. Fixed bands of table rows, summed in order: thread-independent.
template <typename Factor>
std::vector<double> pixel_integrated_lobe(const DiskTable& density, Vec3 omega_i, int resolution, Factor factor) {
    const int n = density.resolution;
    const double cell = 2.0 / n;
    const std::size_t pixels = static_cast<std::size_t>(resolution) * resolution;
    const std::size_t bands = std::clamp<std::size_t>(std::size_t(256e6 / (8.0 * pixels)), 1, 16);
    std::vector<std::vector<double>> partial(bands);
    const auto to_pixels = [&](double x, double y) -> DiskPoint {
        const Vec3 h{x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y))};
        const Vec3 o = 2.0 * dot(omega_i, h) * h - omega_i;
        return {(o.x + 1.0) * 0.5 * resolution, (1.0 - o.y) * 0.5 * resolution};
    };
    parallel_for(bands, 1, [&](std::size_t begin, std::size_t end) {
        // The images of one row of the table's corners, and of the next (each shared by 4 cells).
        std::vector<DiskPoint> upper(n + 1), lower(n + 1);
        const auto map_corners = [&](int row, std::vector<DiskPoint>& images) {
            for (int c = 0; c <= n; ++c) images[c] = to_pixels(-1.0 + c * cell, 1.0 - row * cell);
        };
        for (std::size_t b = begin; b < end; ++b) {
            std::vector<double>& masses = partial[b];
            masses.assign(pixels, 0.0);
            const int r_begin = int(n * b / bands), r_end = int(n * (b + 1) / bands);
            if (r_begin < r_end) map_corners(r_begin, upper);
            for (int r = r_begin; r < r_end; ++r) {
                map_corners(r + 1, lower);
                for (int c = 0; c < n; ++c) {
                    const double d = density.pixel(r, c);
                    if (d <= 0.0) continue;
                    const DiskPoint centre = disk_pixel_point(r, c, n);
                    const Vec3 h = direction_from_disk(centre.x, centre.y);
                    const Vec3 omega_o = 2.0 * dot(omega_i, h) * h - omega_i;
                    if (omega_o.z <= 0.0) continue;  // reflected below the horizon
                    const double albedo = factor(h, omega_o) * d * cell * cell * dot(omega_i, h) / (omega_i.z * h.z);
                    const SmallPolygon quad{{upper[c], upper[c + 1], lower[c + 1], lower[c]}, 4};
                    deposit_polygon(quad, albedo, resolution, masses);
                }
                std::swap(upper, lower);
            }
        }
    });
    // Masses to f_r: albedo = Σ f_r (2/N)²; a pixel whose centre lies outside the disk holds none.
    std::vector<double> values(pixels, 0.0);
    for (int r = 0; r < resolution; ++r)
        for (int c = 0; c < resolution; ++c) {
            if (!inside_unit_disk(disk_pixel_point(r, c, resolution))) continue;
            const std::size_t i = static_cast<std::size_t>(r) * resolution + c;
            double sum = 0.0;
            for (const std::vector<double>& masses : partial) sum += masses[i];
            values[i] = sum / disk_pixel_area(resolution);
        }
    return values;
}

LobeImage geometric_lobe(const LobeQuery& query) {
    const GeometricSettings settings = read_settings(query);
    const DiskTable density = density_table(query, settings);
    const bool smith = settings.shadowing == Shadowing::smith;
    const DiskTable smith_g1 = smith ? smith_table(density) : DiskTable{};
    const NdfFit ellipsoid = settings.shadowing == Shadowing::ellipsoid ? ellipsoid_fit(density) : NdfFit{};
    const Vec3 omega_i = query.omega_i;
    const double g1_i = smith ? smith_g1.at(omega_i.x, omega_i.y) : 1.0;
    const auto shadowing = [&](DiskPoint p, Vec3 omega_o, Vec3 h) {
        switch (settings.shadowing) {
            case Shadowing::none: return 1.0;
            case Shadowing::smith: return g1_i * smith_g1.at(p.x, p.y);
            case Shadowing::ellipsoid:
                return ellipsoid_shadowing_masking(ellipsoid.model.parameters, omega_i, omega_o, h);  // Dong 2015 eq. 13
        }
        return 1.0;
    };
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    const bool has_material = !query.material.name.empty();
    for (std::size_t l = 0; l < query.wavelengths_um.size(); ++l) {
        const ComplexIndex eta =
            has_material ? complex_refractive_index(query.material.name, query.wavelengths_um[l]) : ComplexIndex{};
        const auto fresnel = [&](Vec3 h) { return has_material ? fresnel_conductor(eta, dot(omega_i, h)) : 1.0; };
        if (query.supersample == kExactPixels) {
            const std::vector<double> values = pixel_integrated_lobe(density, omega_i, query.resolution, [&](Vec3 h, Vec3 omega_o) {
                return fresnel(h) * shadowing({omega_o.x, omega_o.y}, omega_o, h);
            });
            std::copy(values.begin(), values.end(), image.values.begin() + l * values.size());
            continue;
        }
        // Point samples of f_r (what a BSDF query evaluates), K×K per pixel.
        fill_by_direction(image, l, query.supersample, [&](DiskPoint p) {
            const Vec3 omega_o = direction_from_disk(p.x, p.y);
            const Vec3 h = normalize(omega_i + omega_o);
            return fresnel(h) * density.at(h.x, h.y) * shadowing(p, omega_o, h) /
                   (4.0 * omega_i.z * omega_o.z);  // Dong 2015 eq. 1
        });
    }
    image.metadata["geometric.ndf"] = settings.filtered ? "filtered" : "pndf";
    image.metadata["geometric.shadowing"] = method_option_text(query, "shadowing", "none");
    if (settings.shadowing == Shadowing::ellipsoid) {
        const EllipsoidNdf& e = ellipsoid.model.parameters;
        image.metadata["geometric.ellipsoid"] = join_numbers({e.alpha_x, e.alpha_y, e.theta_x, e.theta_y, e.theta_z});
        image.metadata["geometric.ellipsoid_relative_error"] = shortest_text(ellipsoid.relative_error);
    }
    image.metadata["geometric.ndf_resolution"] = std::to_string(density.resolution);
    image.metadata["geometric.refinement"] = std::to_string(settings.density.refinement);
    if (settings.filtered) image.metadata["geometric.filter_sigma_um"] = shortest_text(settings.filter_sigma_um);
    return image;
}

// One footprint's BSDF: its NDF table made once and read as the images at supersample 1 read it
// (Dong 2015 eq. 1, G = 1), h sampled from the table (microfacet_answers), where answering from
// the images would remake the ω_i-independent table for every new ω_i. Shadowing (Smith's
// integral or the ellipsoid fit over the table) is answered from the images.
PointAnswers geometric_point(const LobeQuery& query) {
    const GeometricSettings settings = read_settings(query);
    if (settings.shadowing != Shadowing::none) return {};
    return microfacet_answers({density_table(query, settings), refractive_indices(query), {}}, query.wavelengths_um.size());
}

// f_r for any footprint from one tree over the field: the point query of the same triangles
// as the internal table of point-sampled pixels, read at h itself rather than bilinearly; without
// intrinsic roughness also its sampler: h drawn with the point query's own density
// (LazyNormalSampler: made on the first draw or pdf, so eval alone never pays for it),
// ω_o = reflect(ω_i, h), pdf = that density × the half-vector Jacobian.
// Boxes, rotated too, by the query's preimage rule (normal_bounds_tree.hpp). Shadowing needs the
// footprint's whole NDF (Smith's integral, the ellipsoid fit): answered from the images.
PointAnswersAt geometric_point_field(const LobeQuery& query) {
    const GeometricSettings settings = read_settings(query);
    if (settings.shadowing != Shadowing::none) return [](const Footprint&) { return PointAnswers{}; };
    const int resolution = table_resolution(query, settings);
    const NormalDensitySettings density = table_density_settings(query, settings, resolution);
    auto tree = std::make_shared<const NormalBoundsTree>(
        make_normal_bounds_tree(ndf_surface(query, settings), density, resolution));
    auto indices = std::make_shared<const std::vector<ComplexIndex>>(refractive_indices(query));
    const std::size_t layers = query.wavelengths_um.size();
    // One allocation per footprint: the answers point into it (a pointer is stored inside a
    // std::function, a shared_ptr would be allocated again for each) and `owner` keeps it.
    struct OneFootprint {
        OneFootprint(std::shared_ptr<const NormalBoundsTree> tree_in, std::shared_ptr<const std::vector<ComplexIndex>> indices_in,
                     std::size_t layers_in, const Footprint& footprint_in)
            : tree(std::move(tree_in)), indices(std::move(indices_in)), layers(layers_in), footprint(footprint_in),
              normals(tree, footprint) {}
        std::shared_ptr<const NormalBoundsTree> tree;
        std::shared_ptr<const std::vector<ComplexIndex>> indices;
        std::size_t layers;
        Footprint footprint;
        LazyNormalSampler normals;
    };
    return [tree, indices, layers](const Footprint& footprint) -> PointAnswers {
        const auto one = std::make_shared<const OneFootprint>(tree, indices, layers, footprint);
        const OneFootprint* const at = one.get();
        PointAnswers answers;
        answers.owner = one;
        answers.eval = [at](Vec3 omega_i, Vec3 omega_o) {
            const Vec3 h = normalize(omega_i + omega_o);
            return microfacet_value(point_normal_density(*at->tree, at->footprint, {h.x, h.y}), 1.0, omega_i, omega_o, h,
                                    *at->indices, at->layers);
        };
        if (at->tree->intrinsic_roughness > 0.0) return answers;
        answers.sample = [at](Vec3 omega_i, double u1, double u2) -> DirectionSample {
            const std::optional<NormalDraw> h = at->normals.draw(u1, u2);
            if (!h) return {};
            return reflected_sample(omega_i, h->normal, h->density);
        };
        answers.pdf = [at](Vec3 omega_i, Vec3 omega_o) {
            const Vec3 h = normalize(omega_i + omega_o);
            return reflection_pdf(at->normals.density({h.x, h.y}), h, omega_o);
        };
        return answers;
    };
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
                          {"ndf_oversampling", "internal NDF resolution per lobe pixel, 1-4, at least 200 tan(theta_i) across (default 4)"},
                          {"filter_sigma", "plane-fit window sigma_f of the filtered NDF, a length (default 1um)"}};
    for (const MethodOption& option : normal_density_options()) entry.info.options.push_back(option);
    entry.info.whole_field = true;
    entry.info.exact_pixels = true;
    entry.info.elliptical_footprints = true;
    entry.info.rotated_boxes = true;
    entry.compute = geometric_lobe;
    entry.point = geometric_point;
    entry.point_field = geometric_point_field;
    return entry;
}

}  // namespace glintscope
