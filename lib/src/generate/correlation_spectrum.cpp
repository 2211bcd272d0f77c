#include "correlation_spectrum.hpp"

#include <cmath>
#include <cstdlib>

#include "glintscope/core/geometry.hpp"

namespace glintscope {
namespace {

// exp(−x) for x beyond this is below 1e-300: skipping it avoids libm's slow underflow path.
constexpr double kNegligibleExponent = 690.0;
// The lattice sum over far images is truncated here; the remainder is O(1/kFarImages) of an
// already small term (C2's spectrum falls as |k|⁻³).
constexpr int kFarImages = 256;

int signed_index(int index, int count) {
    const int wrapped = ((index % count) + count) % count;
    return wrapped <= count / 2 ? wrapped : wrapped - count;
}

// 1-D factors of the separable correlations, folded over the reciprocal lattice m/dx.
// C1: Σ_m √π T exp(−π²T²(k + m/dx)²), summed until the terms vanish.
double folded_gaussian(double t, double dx, double k) {
    double sum = 0.0;
    const int images = 2 + static_cast<int>(std::ceil(std::sqrt(kNegligibleExponent) * dx / (pi * t)));
    for (int m = -images; m <= images; ++m) {
        const double exponent = pi * pi * t * t * (k + m / dx) * (k + m / dx);
        if (exponent < kNegligibleExponent) sum += std::sqrt(pi) * t * std::exp(-exponent);
    }
    return sum;
}

// C3: Σ_m 2T/(1 + 4π²T²(k + m/dx)²) = dx Σ_n e^{−|n|dx/T} e^{−i2πk n dx}
//   = dx (1 − r²)/(1 − 2r cos(2πk dx) + r²), r = e^{−dx/T} (Poisson summation; the Fourier
// series of the sampled exponential), exact where the lattice sum converges only as 1/m.
double folded_exponential(double t, double dx, double k) {
    const double r = std::exp(-dx / t);
    return dx * (1.0 - r * r) / (1.0 - 2.0 * r * std::cos(2.0 * pi * k * dx) + r * r);
}

}  // namespace

SampledPowerSpectrum::SampledPowerSpectrum(const GaussianFieldParameters& parameters, const GridSpec& grid)
    : parameters_(parameters), grid_(grid) {
    const double dx = grid.dx_um();
    const double dy = grid.dy_um();
    separable_ = parameters.orientation_rad == 0.0 && parameters.correlation != CorrelationFunction::c2;
    if (separable_) {
        const auto folded = [&](double t, double spacing, double k) {
            return parameters.correlation == CorrelationFunction::c1 ? folded_gaussian(t, spacing, k)
                                                                     : folded_exponential(t, spacing, k);
        };
        for (int j = 0; j <= grid.cols / 2; ++j)
            aliased_x_.push_back(folded(parameters.correlation_length_x_um, dx, j / (grid.cols * dx)));
        for (int i = 0; i <= grid.rows / 2; ++i)
            aliased_y_.push_back(folded(parameters.correlation_length_y_um, dy, i / (grid.rows * dy)));
        return;
    }
    // Beyond the nearest 3×3 images the terms vary little across the band [−1/(2dx), 1/(2dx)] ×
    // [−1/(2dy), 1/(2dy)],
    // so they are taken at its centre: one constant, without which C2 would lose the variance
    // of its slowly decaying tail (about 1/(2πT/dx) of the total) and read a longer T.
    for (int m = -kFarImages; m <= kFarImages; ++m)
        for (int n = -kFarImages; n <= kFarImages; ++n)
            if (std::abs(m) > 1 || std::abs(n) > 1) far_images_ += density(m / dx, n / dy);
}

double SampledPowerSpectrum::density(double kx, double ky) const {
    const double tx = parameters_.correlation_length_x_um;
    const double ty = parameters_.correlation_length_y_um;
    const double c = std::cos(parameters_.orientation_rad);
    const double s = std::sin(parameters_.orientation_rad);
    // Frequencies in the frame of the correlation ellipse, scaled by T: U = T_x k_u, V = T_y k_v.
    const double u = tx * (c * kx + s * ky);
    const double v = ty * (-s * kx + c * ky);
    switch (parameters_.correlation) {
        case CorrelationFunction::c1: {
            // A product of 1-D Gaussians: FT of exp(−x²/T²) is √π T exp(−π²T²k²).
            const double exponent = pi * pi * (u * u + v * v);
            return exponent < kNegligibleExponent ? pi * tx * ty * std::exp(-exponent) : 0.0;
        }
        case CorrelationFunction::c2: {
            // The 2-D transform of exp(−r) is 2π/(1 + 4π²|k|²)^{3/2}, stretched by T_x, T_y.
            const double q = 1.0 + 4.0 * pi * pi * (u * u + v * v);
            return 2.0 * pi * tx * ty / (q * std::sqrt(q));
        }
        case CorrelationFunction::c3:
            // A product of 1-D exponentials: FT of exp(−|x|/T) is 2T/(1 + 4π²T²k²).
            return 4.0 * tx * ty / ((1.0 + 4.0 * pi * pi * u * u) * (1.0 + 4.0 * pi * pi * v * v));
    }
    return 0.0;
}

double SampledPowerSpectrum::nearby_images(double kx, double ky) const {
    const double sampling_frequency_x = 1.0 / grid_.dx_um();
    const double sampling_frequency_y = 1.0 / grid_.dy_um();
    double sum = 0.0;
    for (int m = -1; m <= 1; ++m)
        for (int n = -1; n <= 1; ++n) sum += density(kx + m * sampling_frequency_x, ky + n * sampling_frequency_y);
    return sum;
}

double SampledPowerSpectrum::aliased(int i, int j) const {
    const int fi = signed_index(i, grid_.rows);
    const int fj = signed_index(j, grid_.cols);
    if (separable_) return aliased_x_[std::abs(fj)] * aliased_y_[std::abs(fi)];
    const double kx = fj / grid_.width_um();
    const double ky = -fi / grid_.height_um();
    return nearby_images(kx, ky) + far_images_;
}

}  // namespace glintscope
