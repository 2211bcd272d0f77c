// Yan 2018 eq. 6 at single directions (fft_point): the same sum over the same footprint grid as
// the fft image's chirp-z transforms, so it equals the image at pixel centres.
#include <gtest/gtest.h>

#include "glintscope/pipeline/pipeline.hpp"
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

}  // namespace
}  // namespace glintscope
