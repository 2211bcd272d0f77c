// The fit picture's slices: along and across the first fit's α_x axis, a model fitted to an image
// drawn from it lies on the data, and a wrong model departs where its shape differs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/fit/ndf_fit_slices.hpp"

namespace glintscope {
namespace {

double peak(const std::vector<double>& values) { return *std::max_element(values.begin(), values.end()); }

TEST(NdfFitSlices, FollowTheFitsPrincipalAxesAndARecoveredModelLiesOnTheData) {
    const EllipsoidNdf truth{0.3, 0.1, 0.0, 0.0, 0.35};  // α_x axis at −20° on the disk
    const LobeImage data = model_ndf_image({NdfModelKind::ellipsoid, truth}, 96);
    const std::vector<NdfFit> fits = {fit_ndf(data, NdfModelKind::ellipsoid), fit_ndf(data, NdfModelKind::beckmann)};
    const std::vector<NdfFitSlice> slices = ndf_fit_slices(data, fits, 101);
    ASSERT_EQ(slices.size(), 2u);
    EXPECT_NEAR(slices[0].angle_deg, -0.35 * 180.0 / pi, 0.5);
    EXPECT_NEAR(slices[1].angle_deg - slices[0].angle_deg, 90.0, 1e-9);
    // The broad axis is the first: its profile is wider, so its value 10° off the peak is higher.
    const auto at_ten_degrees = [](const NdfFitSlice& slice, const std::vector<double>& values) {
        const auto found = std::lower_bound(slice.theta_deg.begin(), slice.theta_deg.end(), 10.0);
        return values[found - slice.theta_deg.begin()] / peak(values);
    };
    EXPECT_GT(at_ten_degrees(slices[0], slices[0].data), 2.0 * at_ten_degrees(slices[1], slices[1].data));
    for (const NdfFitSlice& slice : slices) {
        ASSERT_EQ(slice.models.size(), 2u);
        const double top = peak(slice.data);
        double ellipsoid_gap = 0.0, beckmann_gap = 0.0;
        for (std::size_t i = 0; i < slice.data.size(); ++i) {
            ellipsoid_gap = std::max(ellipsoid_gap, std::fabs(slice.models[0][i] - slice.data[i]));
            beckmann_gap = std::max(beckmann_gap, std::fabs(slice.models[1][i] - slice.data[i]));
        }
        EXPECT_LT(ellipsoid_gap, 0.01 * top) << slice.angle_deg;  // the fit recovers its own model
        EXPECT_GT(beckmann_gap, 0.05 * top) << slice.angle_deg;   // axes along x, y cannot follow a turned lobe
    }
}

TEST(NdfFitSlices, NeedAFitAndThreeSamples) {
    const LobeImage data = model_ndf_image({NdfModelKind::beckmann, {0.2, 0.2, 0, 0, 0}}, 16);
    EXPECT_THROW(ndf_fit_slices(data, {}, 11), Error);
    EXPECT_THROW(ndf_fit_slices(data, {fit_ndf(data, NdfModelKind::beckmann)}, 2), Error);
}

}  // namespace
}  // namespace glintscope
