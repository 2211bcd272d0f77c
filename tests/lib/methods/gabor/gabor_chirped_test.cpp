// Second-order (chirped) Gabor kernels (docs/gabor.md "Second order"): the closed-form transform
// of a Gaussian times a quadratic phase against quadrature, a paraboloid represented exactly by
// one kernel, the point query against the image, and the lobe against the FFT ground truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "glintscope/core/parallel.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/lobe/compare.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "methods/gabor/gabor.hpp"
#include "methods/gabor/gabor_kernels.hpp"

namespace glintscope {
namespace {

using Complex = std::complex<double>;

// ∫ f(s) e^{−i2π v·s} ds over ±8σ about `centre`, a Riemann sum at step σ/40: for a Gaussian
// envelope sampled far above the integrand's local frequencies it converges far below 1e-6.
template <typename F>
Complex quadrature(Point2 centre, double sigma, Point2 v, F&& f) {
    const double step = sigma / 40.0;
    const int half = 320;
    Complex sum = 0.0;
    for (int j = -half; j <= half; ++j)
        for (int i = -half; i <= half; ++i) {
            const Point2 s{centre.x + i * step, centre.y + j * step};
            const double phase = -2.0 * pi * (s.x * v.x + s.y * v.y);
            sum += f(s) * Complex(std::cos(phase), std::sin(phase));
        }
    return sum * step * step;
}

// Chirps from mild to strong (ε = 2πσ²|B| up to ~5), one with det(M) of negative real part
// (both eigenvalues of B of one sign, ε₁ε₂ > 1) and one indefinite (a saddle).
TEST(ChirpedGaborKernel, TransformMatchesQuadrature) {
    const std::vector<Chirp> chirps = {{0.3, 0.1, -0.2}, {2.0, 0.5, 1.5}, {-3.0, 1.0, -2.5}, {1.2, 2.0, -0.7}};
    for (const Chirp& chirp : chirps) {
        const GaborKernel kernel{{3.2, -1.7}, 0.5, {0.8, -0.3}, chirp};
        for (const Point2 v : {Point2{-0.8, 0.3}, Point2{-0.5, 0.1}, Point2{0.2, 0.4}, Point2{-1.3, 0.9}}) {
            const Complex numeric =
                quadrature(kernel.centre_um, kernel.sigma_um, v, [&](Point2 s) { return gabor_kernel_value(kernel, s); });
            const Complex closed = gabor_kernel_transform(kernel, v);
            EXPECT_LT(std::abs(closed - numeric), 1e-6 * std::max(1e-3, std::abs(numeric)))
                << "B = (" << chirp.xx << ", " << chirp.xy << ", " << chirp.yy << "), v = (" << v.x << ", " << v.y << ")";
        }
    }
}

// H(s) = h0 + g·s + ½ (s − s0)ᵀP(s − s0), sampled at 1 µm: the interpolant reproduces quadratics,
// so H, H' and H'' at any kernel centre are exact, and one second-order kernel is the whole
// reflection function under its Gaussian. Its C_k F[g_k](v) must equal quadrature of
// l² ξ2 G_2D(s − m; l/2) e^{−i2π ξ3 H(s)/λ}, at a sample (K = 1, where the one-sided second
// derivatives meet) and between samples (K = 2). A first-order kernel misses by far more.
TEST(ChirpedGaborKernel, ParaboloidIsRepresentedExactlyByOneKernel) {
    const double pxx = 0.35, pxy = -0.12, pyy = 0.22;  // 1/µm
    const Point2 s0{20.3, 19.1};
    const auto height = [&](Point2 s) {
        const double dx = s.x - s0.x, dy = s.y - s0.y;
        return 0.4 + 0.05 * s.x - 0.03 * s.y + 0.5 * (pxx * dx * dx + 2.0 * pxy * dx * dy + pyy * dy * dy);
    };
    Heightfield field = make_heightfield(40, 40, 1.0);
    for (int row = 0; row < field.rows; ++row)
        for (int col = 0; col < field.cols; ++col)  // row 0 is the top: y = (rows − 1 − row + ½) dx
            field.at(row, col) = static_cast<float>(height({col + 0.5, field.rows - 1 - row + 0.5}));
    const BicubicInterpolant surface(field);
    const double xi2 = 0.9, xi3 = 1.7, lambda = 0.55;
    for (const auto& [centre, cell] : {std::pair{Point2{20.5, 18.5}, 1.0}, std::pair{Point2{19.75, 20.25}, 0.5}}) {
        const SurfaceCurvature curvature = surface.curvature(centre.x, centre.y);
        // float samples: the quadratic is reproduced to their rounding
        EXPECT_NEAR(curvature.d2h_dx2, pxx, 1e-4);
        EXPECT_NEAR(curvature.d2h_dxdy, pxy, 1e-4);
        EXPECT_NEAR(curvature.d2h_dy2, pyy, 1e-4);
        // The kernel from the exact H, H', H'' (the float samples' rounding is the interpolant's
        // business, checked above), against quadrature of the exact paraboloid.
        const double dx = centre.x - s0.x, dy = centre.y - s0.y;
        const SurfacePoint exact{height(centre), 0.05 + pxx * dx + pxy * dy, -0.03 + pxy * dx + pyy * dy};
        const GaborCellKernel second =
            gabor_cell_kernel(centre, cell, exact, {pxx, pxy, pyy}, xi2, xi3, lambda);
        const GaborCellKernel first = gabor_cell_kernel(centre, cell, exact, xi2, xi3, lambda);
        double worst_first_order = 0.0;
        for (const Point2 v : {Point2{-0.3, 0.2}, Point2{0.1, -0.4}, Point2{-0.9, 0.6}}) {
            const double sigma = 0.5 * cell;
            const Complex numeric = quadrature(centre, sigma, v, [&](Point2 s) {
                const double d2 = (s.x - centre.x) * (s.x - centre.x) + (s.y - centre.y) * (s.y - centre.y);
                const double gaussian = std::exp(-d2 / (2.0 * sigma * sigma)) / (2.0 * pi * sigma * sigma);
                const double phase = -2.0 * pi * xi3 * height(s) / lambda;
                return cell * cell * xi2 * gaussian * Complex(std::cos(phase), std::sin(phase));
            });
            const Complex closed = second.coefficient * gabor_kernel_transform(second.kernel, v);
            EXPECT_LT(std::abs(closed - numeric), 1e-6 * std::abs(numeric)) << "cell " << cell;
            const Complex linear = first.coefficient * gabor_kernel_transform(first.kernel, v);
            worst_first_order = std::max(worst_first_order, std::abs(linear - numeric) / std::abs(numeric));
        }
        EXPECT_GT(worst_first_order, 0.01) << "cell " << cell;
    }
}

// The kernel sum's second-order term (gabor_kernels.cpp, SIMD lanes and scalar tail) equals the
// literal C_k F[g_k](v) up to the common phase it drops.
TEST(ChirpedGaborKernel, SummedTermEqualsLiteralTransform) {
    const SurfacePoint at_centre{0.37, 0.21, -0.14};
    const SurfaceCurvature curvature{0.8, -0.3, 0.5};
    const Point2 centre{13.25, -7.75};
    const Point2 x_c{10.0, -5.0};
    const double reference_height = 0.05, cell = 0.5, lambda = 0.45, xi3 = 1.8;
    GaborSettings settings;
    settings.kernels_per_texel = 2;
    settings.kernel_sigmas = 5.0;
    settings.order = 2;
    const gabor::KernelGrid grid = gabor::kernel_grid(1.0, settings);
    gabor::KernelArrays kernels;
    kernels.reserve_more(5);
    for (int k = 0; k < 5; ++k) {  // four in SIMD lanes, one in the scalar tail
        kernels.push(centre.x - x_c.x, centre.y - x_c.y, at_centre, reference_height, cell * cell);
        kernels.set_curvature(k, curvature);
    }
    const GaborCellKernel literal = gabor_cell_kernel(centre, cell, at_centre, curvature, 1.0, xi3, lambda);
    for (const Point2 v : {Point2{-0.9, 0.5}, Point2{-0.6, 0.2}, Point2{0.4, 0.1}}) {
        const Complex expected = literal.coefficient * gabor_kernel_transform(literal.kernel, v);
        gabor::TransformPoint point;
        point.vx = v.x;
        point.vy = v.y;
        point.xi3_over_lambda = xi3 / lambda;
        const double common = 2.0 * pi * (x_c.x * v.x + x_c.y * v.y + xi3 * reference_height / lambda);
        const Complex phase(std::cos(common), -std::sin(common));
        EXPECT_LT(std::abs(gabor::sum_transforms(kernels, 0, 4, point, grid) * phase - 4.0 * expected),
                  4e-9 * std::abs(expected));
        EXPECT_LT(std::abs(gabor::sum_transforms(kernels, 4, 5, point, grid) * phase - expected),
                  1e-9 * std::abs(expected));
    }
}

}  // namespace
}  // namespace glintscope
