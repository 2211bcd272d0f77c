// Yan 2018 eq. 6 at single directions (fft_point): the same sum over the same footprint grid as
// the fft image's chirp-z transforms, so it equals the image at pixel centres.
#include <gtest/gtest.h>

#include "core/counter_rng.hpp"
#include "glintscope/bsdf/bsdf.hpp"
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
