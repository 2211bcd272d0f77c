#include "methods/dk/kirchhoff_distribution.hpp"

#include <algorithm>

#include "glintscope/core/error.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/core/text_format.hpp"
#include "methods/fft/fft_lobe.hpp"
#include "normal_density/microfacet_answers.hpp"
#include "numerics/disk_table.hpp"

namespace glintscope {
namespace {

constexpr double kDongLambdaQUm = 0.555;

// λ_q in µm, or 0 for "per-pixel".
double lambda_q_um(const LobeQuery& query) {
    if (method_option_text(query, "lambda_q", "") == "per-pixel") {
        if (query.quantity == Quantity::ndf)
            throw Error("option lambda_q=per-pixel needs the brdf quantity (an NDF has no incident direction)");
        return 0.0;
    }
    const double lambda_q = method_option_length_um(query, "lambda_q", kDongLambdaQUm);
    if (!(lambda_q >= 0.1 && lambda_q <= 20.0))
        throw Error("option lambda_q must be between 0.1 and 20 um, got " + shortest_text(lambda_q) + " um");
    return lambda_q;
}

// D_K over h on an N×N disk image at λ_q (one layer), K×K supersampled as the query asks.
LobeImage distribution_image(const LobeQuery& query, double lambda_q, int resolution) {
    LobeQuery kirchhoff = query;
    kirchhoff.model = DiffractionModel::kirchhoff;
    kirchhoff.resolution = resolution;
    LobeImage image = make_lobe_image(resolution, {lambda_q}, Quantity::ndf);
    // Dong 2015 eq. 6 with ψ = 2h: D_K = ψ_z² |R̃*|²/(λ_q² A_c).
    scattering_layers(kirchhoff, {Vec3{0.0, 0.0, 0.0}, 2.0},
                      [](const Vec3& psi, const Vec3&, double) { return psi.z * psi.z; }, image);
    return image;
}

LobeImage distribution_ndf(const LobeQuery& query, double lambda_q) {
    const LobeImage one = distribution_image(query, lambda_q, query.resolution);
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um, Quantity::ndf);
    std::copy(one.values.begin(), one.values.end(), image.values.begin());
    copy_first_layer_to_all(image);
    image.metadata = one.metadata;
    return image;
}

// Dong 2015 eq. 7 with λ_q = 2λ/|ψ| (eq. 5): q = 2πψ/λ, the Kirchhoff integral at every ω_o.
LobeImage per_pixel_lobe(const LobeQuery& query, const std::vector<ComplexIndex>& indices) {
    LobeQuery kirchhoff = query;
    kirchhoff.model = DiffractionModel::kirchhoff;
    const bool has_material = !indices.empty();
    const Vec3 omega_i = query.omega_i;
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    scattering_layers(kirchhoff, {omega_i, 1.0},
                      [&](const Vec3& psi, const Vec3& omega_o, double lambda) {
                          const std::size_t layer = static_cast<std::size_t>(
                              std::find(query.wavelengths_um.begin(), query.wavelengths_um.end(), lambda) -
                              query.wavelengths_um.begin());
                          const double fresnel =
                              has_material ? fresnel_conductor(indices[layer], 0.5 * length(psi)) : 1.0;
                          return psi.z * psi.z * fresnel / (4.0 * omega_i.z * omega_o.z);  // Dong 2015 eq. 7
                      },
                      image);
    return image;
}

// D_K at a fixed λ_q, tabulated finer than the lobe (option ndf_oversampling), with the grid's metadata.
struct KirchhoffTable {
    DiskTable table;
    Provenance metadata;
};

KirchhoffTable kirchhoff_table(const LobeQuery& query, double lambda_q) {
    const int oversampling = method_option_integer(query, "ndf_oversampling", 2, 1, 4);
    const int table_resolution = std::min(query.resolution * oversampling, 8192);
    const LobeImage distribution = distribution_image(query, lambda_q, table_resolution);
    KirchhoffTable result{{table_resolution, std::vector<double>(distribution.values.begin(), distribution.values.end())},
                          distribution.metadata};
    result.metadata["dk.ndf_resolution"] = std::to_string(table_resolution);
    return result;
}

// Dong 2015 eq. 8 (G = 1) from the table.
LobeImage fixed_lambda_lobe(const LobeQuery& query, double lambda_q, const std::vector<ComplexIndex>& indices) {
    const KirchhoffTable kirchhoff = kirchhoff_table(query, lambda_q);
    const DiskTable& table = kirchhoff.table;
    const Vec3 omega_i = query.omega_i;
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    for (std::size_t layer = 0; layer < image.layers(); ++layer)
        fill_by_direction(image, layer, query.supersample, [&](DiskPoint p) {
            const Vec3 omega_o = direction_from_disk(p.x, p.y);
            const Vec3 h = normalize(omega_i + omega_o);
            const double fresnel = indices.empty() ? 1.0 : fresnel_conductor(indices[layer], dot(omega_i, h));
            return fresnel * table.at(h.x, h.y) / (4.0 * omega_i.z * omega_o.z);  // Dong 2015 eq. 8, G = 1
        });
    image.metadata = kirchhoff.metadata;
    return image;
}

LobeImage kirchhoff_distribution(const LobeQuery& query) {
    const double lambda_q = lambda_q_um(query);
    if (query.quantity == Quantity::ndf) {
        LobeImage image = distribution_ndf(query, lambda_q);
        image.metadata["dk.lambda_q_um"] = shortest_text(lambda_q);
        image.metadata["not_applicable"] = "omega_i,lambda,material";  // λ_q replaces λ; an NDF has no ω_i
        return image;
    }
    const std::vector<ComplexIndex> indices = refractive_indices(query);
    LobeImage image = lambda_q > 0.0 ? fixed_lambda_lobe(query, lambda_q, indices) : per_pixel_lobe(query, indices);
    image.metadata["dk.lambda_q_um"] = lambda_q > 0.0 ? shortest_text(lambda_q) : "per-pixel";
    return image;
}

// At a fixed λ_q the lobe is a microfacet lobe over the footprint's D_K table; per-pixel λ_q is
// the Kirchhoff lobe itself, answered from the images.
PointAnswers kirchhoff_point(const LobeQuery& query) {
    const double lambda_q = lambda_q_um(query);
    if (lambda_q == 0.0) return {};
    return microfacet_answers({kirchhoff_table(query, lambda_q).table, refractive_indices(query), {}},
                              query.wavelengths_um.size());
}

}  // namespace

MethodEntry dk_method() {
    MethodEntry entry;
    entry.info.name = "dk";
    entry.info.description = "Kirchhoff distribution D_K(4 pi h / lambda_q) and its BRDF F D_K / (4 cos cos)";
    entry.info.reference = "Dong 2015 eq. 6-8";
    entry.info.quantities = {Quantity::ndf, Quantity::brdf};
    entry.info.ignored = {QueryField::model};
    entry.info.options = {{"lambda_q", "effective wavelength, a length, or per-pixel (brdf: 2 lambda/|omega_i + omega_o|, "
                                       "the Kirchhoff lobe itself) (default 0.555um)"},
                          {"ndf_oversampling", "brdf at a fixed lambda_q: D_K table resolution per lobe pixel, 1-4 "
                                               "(default 2)"}};
    for (const MethodOption& option : fft_options()) entry.info.options.push_back(option);
    entry.info.wave_optics = true;
    entry.compute = kirchhoff_distribution;
    entry.point = kirchhoff_point;
    return entry;
}

}  // namespace glintscope
