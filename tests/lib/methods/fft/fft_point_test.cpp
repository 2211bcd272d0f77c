// Yan 2018 eq. 6 at single directions (fft_point): the same sum over the same footprint grid as
// the fft image's chirp-z transforms, so it equals the image at pixel centres.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "core/counter_rng.hpp"
#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/optics/diffraction_model.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "mean_weight.hpp"
#include "method_cases.hpp"
#include "methods/fft/fft_lobe.hpp"

namespace glintscope {
namespace {

TEST(FftPoint, EqualsTheImageAtPixelCentres) {
    LobeQuery query = testing::isotropic_builtin_query(Quantity::brdf);
    query.resolution = 24;
    query.supersample = 1;
    query.omega_i = direction_from_spherical(30.0 * pi / 180.0, 0.4);
    const LobeImage image = compute_lobe("fft", query);
    const PointAnswers point = fft_point(query);
    double peak = 0.0;
    for (int row = 0; row < query.resolution; ++row)
        for (int col = 0; col < query.resolution; ++col) {
            const DiskPoint p = disk_pixel_point(row, col, query.resolution);
            if (!inside_unit_disk(p)) continue;
            const std::vector<double> f = point.eval(query.omega_i, direction_from_disk(p.x, p.y));
            for (std::size_t layer = 0; layer < image.layers(); ++layer) {
                peak = std::max(peak, f[layer]);
                ASSERT_NEAR(f[layer], image.at(layer, row, col), 1e-4 * image.at(layer, row, col))
                    << row << "," << col << " layer " << layer;
            }
        }
    EXPECT_GT(peak, 1.0);  // the lobe's peak is among the pixels
}

// Yan 2018 eq. 6 summed plainly over the footprint grid, a sincos per sample and direction:
// ξ1/(A_c λ²) |Σ_s R*(s) e^{−i2π ψ̄·s/λ} ΔxΔy|², R* = w e^{−i2π ξ3 (H − H̄)/λ} (no Fresnel factor).
double direct_sum(const LobeQuery& query, const FootprintSamples& s, Vec3 omega_i, Vec3 omega_o, double lambda) {
    const Vec3 psi = omega_i + omega_o;
    const double xi3 = phase_depends_on_outgoing(query.model) ? psi.z : 2.0;
    std::complex<double> sum = 0.0;
    for (int k = 0; k < s.y.count; ++k)
        for (int j = 0; j < s.x.count; ++j) {
            const std::size_t at = static_cast<std::size_t>(k) * s.x.count + j;
            const double x = s.x.first_um + j * s.x.step_um, y = s.y.first_um + k * s.y.step_um;
            sum += s.weight[at] * std::polar(1.0, -2.0 * pi * (xi3 * s.height[at] + psi.x * x + psi.y * y) / lambda);
        }
    const double cell = s.x.step_um * s.y.step_um;
    const double area = footprint_extent(query.footprint, fft_settings(query).window_sigmas).area_um2;
    return xi1_geometric(query.model, omega_i, omega_o) * std::norm(sum * cell) / (area * lambda * lambda);
}

// OHS and R-OHS read each row's transform from its oversampled spectrum (row_spectra.hpp), GHS
// sums the grid directly: both equal the plain double-precision sum to 1e-9 wherever the lobe is
// above 1e-6 of its peak (the spectra's error is ~1e-14 of Σ|R*|, so ~1e-11 of the value
// there), and within 1e-9 of the peak below.
TEST(FftPoint, EqualsThePlainSumOverTheGrid) {
    LobeQuery query = testing::isotropic_builtin_query(Quantity::brdf);
    query.footprint.sigma_um = 3.0;
    const Vec3 omega_i = direction_from_spherical(30.0 * pi / 180.0, 0.4);
    for (DiffractionModel model : {DiffractionModel::rohs, DiffractionModel::ohs, DiffractionModel::ghs}) {
        query.model = model;
        const PointAnswers point = fft_point(query);
        std::vector<FootprintSamples> grids;
        for (double lambda : query.wavelengths_um) grids.push_back(layer_samples(query, {omega_i, 1.0}, lambda));
        std::vector<std::vector<double>> evals, sums;
        double peak = 0.0;
        for (int row = 0; row < 10; ++row)
            for (int col = 0; col < 10; ++col) {
                const DiskPoint p = disk_pixel_point(row, col, 10);
                if (!inside_unit_disk(p)) continue;
                const Vec3 omega_o = direction_from_disk(p.x, p.y);
                evals.push_back(point.eval(omega_i, omega_o));
                sums.emplace_back();
                for (std::size_t layer = 0; layer < grids.size(); ++layer) {
                    sums.back().push_back(direct_sum(query, grids[layer], omega_i, omega_o, query.wavelengths_um[layer]));
                    peak = std::max(peak, sums.back().back());
                }
            }
        for (std::size_t d = 0; d < evals.size(); ++d)
            for (std::size_t layer = 0; layer < evals[d].size(); ++layer) {
                const double expected = sums[d][layer];
                EXPECT_NEAR(evals[d][layer], expected, expected > 1e-6 * peak ? 1e-9 * expected : 1e-9 * peak)
                    << to_string(model) << " direction " << d << " layer " << layer;
            }
    }
}

// The BSDF of any footprint answers with the point evaluation: BsdfField::at a footprint other
// than the query's equals the fft image of that footprint at pixel centres, and make_bsdf
// evaluates directly.
TEST(FftPoint, AnyFootprintsBsdfEqualsItsImage) {
    LobeQuery query = testing::isotropic_builtin_query(Quantity::brdf);
    query.resolution = 16;
    query.supersample = 1;
    query.omega_i = direction_from_spherical(20.0 * pi / 180.0, 1.0);
    EXPECT_TRUE(make_bsdf("fft", query).evaluates_directly());
    const BsdfField field = make_bsdf_field("fft", query);
    query.footprint.centre_um = {300.0, 700.0};
    query.footprint.sigma_um = 6.0;
    const Bsdf bsdf = field.at(query.footprint);
    const LobeImage image = compute_lobe("fft", query);
    for (int row = 0; row < query.resolution; ++row)
        for (int col = 0; col < query.resolution; ++col) {
            const DiskPoint p = disk_pixel_point(row, col, query.resolution);
            if (!inside_unit_disk(p)) continue;
            const std::vector<double> f = bsdf.eval(query.omega_i, direction_from_disk(p.x, p.y));
            for (std::size_t layer = 0; layer < image.layers(); ++layer)
                ASSERT_NEAR(f[layer], image.at(layer, row, col), 1e-4 * image.at(layer, row, col)) << row << "," << col;
        }
}

// The weight is honest: sampled from the tabulated lobe (the image at N = 32), weighted by the point
// evaluation, its mean is ∫ f_r cosθ_o dω_o, which albedo() computes as the image's disk sum at
// supersample 4 (the BSDF's quadrature of eval).
TEST(FftPoint, MeanWeightOfTheTabulatedSamplerIsTheAlbedo) {
    LobeQuery query = testing::isotropic_builtin_query(Quantity::brdf);
    query.resolution = 32;
    query.footprint.sigma_um = 5.0;  // a quarter of the grid: each eval a quarter of the time
    const Bsdf bsdf = make_bsdf("fft", query);
    for (double degrees : {0.0, 30.0}) {
        const Vec3 omega_i = direction_from_spherical(degrees * pi / 180.0, 0.4);
        const std::vector<double> albedo = bsdf.albedo(omega_i);
        const testing::MeanWeight weights = testing::mean_weight(bsdf, omega_i, 4000, CounterRng(22, 9));
        for (std::size_t layer = 0; layer < albedo.size(); ++layer)
            EXPECT_NEAR(weights.mean[layer], albedo[layer], 3.0 * weights.standard_error[layer])
                << degrees << " degrees, layer " << layer << ": mean " << weights.mean[layer] << " s.e. "
                << weights.standard_error[layer];
    }
}

}  // namespace
}  // namespace glintscope
