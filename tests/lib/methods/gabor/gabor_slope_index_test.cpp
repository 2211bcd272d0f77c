// A footprint's kernels sorted by slope (gabor_slope_index.hpp): summing only the cells a
// direction can reach gives the sum over every kernel, at both orders and for every model (also
// with second-order factors prepared per wavelength), and a
// footprint's Bsdf (which evaluates through the index) equals the hierarchy's point query.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <memory>
#include <random>
#include <vector>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/generate/generate.hpp"
#include "methods/gabor/gabor.hpp"
#include "methods/gabor/gabor_kernels.hpp"
#include "methods/gabor/gabor_slope_index.hpp"
#include "single_precision.hpp"

namespace glintscope {
namespace {

const std::shared_ptr<const BicubicInterpolant>& isotropic_surface() {
    static const auto surface = std::make_shared<const BicubicInterpolant>(generate_builtin("isotropic"));
    return surface;
}

// Directions spread over the hemisphere, half of them near ω_i's mirror direction where most
// kernels reach.
std::vector<Vec3> test_directions(Vec3 omega_i) {
    std::mt19937_64 rng(25);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Vec3> directions;
    while (directions.size() < 200) {
        const bool near_mirror = directions.size() % 2 == 0;
        const double x = near_mirror ? -omega_i.x + 0.15 * u(rng) : u(rng);
        const double y = near_mirror ? -omega_i.y + 0.15 * u(rng) : u(rng);
        if (x * x + y * y < 0.995) directions.push_back(direction_from_disk(x, y));
    }
    return directions;
}

TEST(GaborSlopeIndex, ReachingCellsSumToTheSumOverEveryKernel) {
    const Vec3 omega_i = direction_from_spherical(0.45, 0.8);
    for (const int order : {1, 2})
        for (const DiffractionModel model : {DiffractionModel::rohs, DiffractionModel::ghs, DiffractionModel::kirchhoff}) {
            GaborSettings settings;
            settings.order = order;
            const gabor::KernelGrid grid = gabor::kernel_grid(isotropic_surface()->texel_um(), settings);
            Footprint footprint;
            footprint.centre_um = {311.0, 702.5};
            footprint.sigma_um = 8.0;
            const gabor::CoherenceWindow window(footprint, settings.footprint_sigmas);
            const gabor::KernelArrays all =
                gabor::gather_kernels(*isotropic_surface(), grid, window, footprint.centre_um).arrays;
            const std::vector<double> wavelengths = {0.4, 0.7};
            // Where ξ3 is fixed (R-OHS), also with second-order factors prepared per wavelength.
            std::vector<double> prepared;
            if (!phase_depends_on_outgoing(model))
                for (const double lambda : wavelengths) prepared.push_back(xi3(model, {0, 0, 1}, {0, 0, 1}) / lambda);
            const gabor::SlopeIndex index(all, grid);
            const gabor::SlopeIndex prepared_index(all, grid, prepared);
            ASSERT_EQ(index.kernels().size(), all.size());
            // |Σ| ≤ Σ_k w_k |ξ2| e^{...} ≤ Σ w_k max|ξ2|: differences in summation order stay far below it.
            double weights = 0.0;
            for (std::size_t k = 0; k < all.size(); ++k) weights += all.weight[k];
            int reached = 0;
            for (const double lambda : wavelengths)
                for (const Vec3 omega_o : test_directions(omega_i)) {
                    const gabor::TransformPoint point = gabor::transform_point(
                        model, gabor::FresnelAtWavelength({}, lambda), omega_i, omega_o, lambda, window.area_um2());
                    const std::complex<double> every = gabor::sum_transforms(all, 0, all.size(), point, grid);
                    const std::complex<double> indexed = index.sum(point);
                    EXPECT_LT(std::abs(indexed - every), 1e-12 * 2.0 * weights)
                        << "order " << order << ", model " << static_cast<int>(model) << ", lambda " << lambda;
                    EXPECT_LT(std::abs(prepared_index.sum(point) - every), 1e-12 * 2.0 * weights)
                        << "prepared, order " << order << ", model " << static_cast<int>(model) << ", lambda " << lambda;
                    reached += std::abs(every) > 1e-3 * weights;
                }
            EXPECT_GT(reached, 100) << "the comparisons are of lobes, not of zeros";
        }
}

TEST(GaborSlopeIndex, FootprintBsdfEqualsTheHierarchysPointQuery) {
    LobeQuery query;
    static const Heightfield field = generate_builtin("isotropic");
    set_heightfield(query, field);
    query.footprint.centre_um = {512.0, 100.0};
    query.footprint.sigma_um = 10.0;
    query.wavelengths_um = {0.45, 0.6};
    query.resolution = 64;
    for (const int order : {1, 2}) {
        query.method_options["order"] = std::to_string(order);
        const Bsdf bsdf = make_bsdf("gabor", query);
        GaborSettings settings;
        settings.order = order;
        const GaborSurface surface(isotropic_surface(), settings);
        const Vec3 omega_i = direction_from_spherical(0.3, 2.0);
        std::vector<std::vector<double>> indexed, walked;  // per direction, per wavelength
        for (const Vec3 omega_o : test_directions(omega_i)) {
            indexed.push_back(bsdf.eval(omega_i, omega_o));
            walked.push_back(
                surface.f_r({query.footprint, omega_i, omega_o, query.model, query.material}, query.wavelengths_um));
        }
        // At second order the walk's spectral sums are single precision, the index's double.
        for (std::size_t w = 0; w < query.wavelengths_um.size(); ++w) {
            double brightest = 0.0;
            for (const std::vector<double>& values : walked) brightest = std::max(brightest, values[w]);
            for (std::size_t d = 0; d < walked.size(); ++d)
                EXPECT_NEAR(indexed[d][w], walked[d][w],
                            order == 1 ? 1e-9 * walked[d][w] + 1e-12 : single_precision_tolerance(walked[d][w], brightest))
                    << "order " << order;
        }
    }
}

}  // namespace
}  // namespace glintscope
