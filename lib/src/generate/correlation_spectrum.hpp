#pragma once
// The power spectral density of Stam's correlation functions (Stam 1999 §4.1, Stam 1999 eq. 15 with m = 1)
// as seen by a sampled, periodic grid: the filter of the Gaussian random field generator.
#include <vector>

#include "glintscope/generate/generate.hpp"

namespace glintscope {

class SampledPowerSpectrum {
public:
    SampledPowerSpectrum(const GaussianFieldParameters& parameters, const GridSpec& grid);

    // The analytic 2-D transform S(k) = ∫ C(s) e^{−i2π k·s} ds at k in cycles per µm.
    double density(double kx, double ky) const;

    // S folded into the sampling band, Σ_(m,n) S(kx + m/dx, ky + n/dy) over the reciprocal lattice
    // (m, n) ∈ Z², at the DFT bin (row i, column j), where kx = j/(cols·dx) and ky = −i/(rows·dy)
    // (indices taken modulo the grid, signed; row index runs along −y). By Poisson summation this
    // equals dx·dy times the DFT of C sampled on the periodic grid, so a field filtered by its square root has
    // covariance C at the sample lags.
    double aliased(int i, int j) const;

private:
    double nearby_images(double kx, double ky) const;

    GaussianFieldParameters parameters_;
    GridSpec grid_;
    bool separable_ = false;
    std::vector<double> aliased_x_;  // separable case: the folded 1-D factors by |frequency index|
    std::vector<double> aliased_y_;
    double far_images_ = 0.0;        // non-separable case: the images beyond the nearest 3×3
};

}  // namespace glintscope
