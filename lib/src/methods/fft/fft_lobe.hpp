#pragma once
// The FFT ground truth of a wave-optics lobe (Yan 2018 §3.2, Yan 2018 eq. 3, 4, 6):
//   f_r(ω_i, ω_o) = ξ1/A_c · |R̃*(ψ̄/λ)|²,   R*(s) = w(s − x_c) ξ2 e^{−i2π ξ3 H(s)/λ},
// with H and H' taken from the shared BicubicInterpolant on a fine regular grid over the
// footprint, and R̃* evaluated exactly at every sub-pixel's ψ̄/λ by separable chirp-z transforms
// (rows, then columns). GHS, R-GHS and Kirchhoff, whose ξ3 = ψ·n varies over the image, are
// transformed at several ξ3 and interpolated per pixel with a stated error bound.
//
// Method options (LobeQuery::method_options):
//   step         grid step, a length (both axes). Default, per wavelength and axis: the largest
//                step whose spectral repeats of R̃* (at v + k/step) stay clear of every ψ̄/λ of
//                the image, 1/step ≥ (max|ψ̄| + q·max ξ3·max|H'|)/λ + guard, with max|H'| over
//                the footprint and q the oversampling, rounded down (a Gaussian footprint) so
//                that it divides the image's period P = 1/Δv (Δv its sub-pixel spacing in ψ̄/λ)
//                into a fast FFT size F = P/step: then the chirp-z transforms fold the grid onto
//                F bins and take one FFT of F points (chirp_z.hpp). The step depends on the
//                image's resolution and supersampling through P, by under 10%; the lobe by the
//                grid's own discretisation (~1e-5 relative L2).
//   window       Gaussian footprint: sampled half-width in σ_c (default 4). Ignored for a box.
//   guard        spectral margin in footprint spectral widths — 1/(2πσ_c) for a Gaussian
//                (default 6: aliased amplitude ≲ e^{−18}), 1/side for a box (default 32).
//   oversampling q above (default 3): the shared interpolant is only C¹, so R̃* has algebraic
//                tails beyond ξ3·max|H'|/λ; q = 3 brings their aliases to ~1e-4 of the lobe
//                where it exceeds 1e-3 of its peak (q = 1: ~1e-2).
//   phase_error  GHS, R-GHS, Kirchhoff: bound ε on the ξ3 interpolation error, in units of a flat
//                mirror's peak amplitude ∫|w| ds (default 0.01).
// The metadata records per wavelength "fft.step_um", "fft.grid", "fft.xi3_slices".
#include <complex>
#include <functional>
#include <vector>

#include "wave/footprint_grid.hpp"

#include "lobe/method.hpp"

namespace glintscope {

// The same transform for any ψ affine in the image's direction: ψ = offset + scale·ω for the
// direction ω of each (sub-)pixel. A lobe: offset ω_i, scale 1. Dong 2015's Kirchhoff
// distribution over h: offset 0, scale 2 (q = 4πh/λ_q = 2π(2h)/λ_q).
struct ScatteringGeometry {
    Vec3 offset;
    double scale = 1.0;
};

// The factor of |R̃*(ψ̄/λ)|²/(A_c λ²) at a sub-pixel, from its ψ, its direction ω and λ
// (a lobe: ξ1·λ² of Yan 2018 Fig. 6 with the Fresnel factor).
using ScatteringFactor = std::function<double(const Vec3& psi, const Vec3& omega, double lambda_um)>;

// A field other than the exact R* to transform (the Gabor method's kernel sum): at a ξ3 node, its
// components on the footprint grid, index k·x.count + j for s = (x_j, y_k): R*, and for Kirchhoff
// H_x R* and H_y R* (ξ2 is applied by the transforms), with heights taken about the grid's
// mean_height_um. `bandwidth` (cycles/µm) is the field's spectral reach beyond its local
// frequencies ξ3 H'/λ, added to the alias-free step's guard; its local frequencies need no
// oversampling (q = 1) when `smooth` is set.
struct ReflectionSource {
    std::function<void(const FootprintSamples& grid, double xi3, double lambda_um,
                       std::vector<std::vector<std::complex<double>>>& components)>
        fill;
    double bandwidth = 0.0;
    bool smooth = false;
};

// Fills every layer λ of `image` (resolution and wavelengths set) with the K×K sub-pixel mean of
// factor · |R̃*(ψ̄/λ)|²/(A_c λ²), R̃* of the query's model, footprint and options as above (or of
// `source`'s field), and records the grid in the metadata ("fft.*"). Throws Error on a bad option
// or a grid too large.
void scattering_layers(const LobeQuery& query, const ScatteringGeometry& geometry, const ScatteringFactor& factor,
                       LobeImage& image, const ReflectionSource* source = nullptr);

// The footprint grid that scattering_layers samples for one wavelength (its step alias-free for
// the geometry and dividing the period of the query's image, or the option's; edges truncated as
// the options say), without `source`: the point evaluation of a query at supersample 1 reads the
// grid of that query's image.
FootprintSamples layer_samples(const LobeQuery& query, const ScatteringGeometry& geometry, double lambda_um);

// Yan 2018 eq. 6 at single directions (fft_point.cpp): for each ω_i and wavelength the grid of
// layer_samples (made on first use; the 16 most recent are kept), then R̃*(ψ̄/λ) over it, so
// that eval is the image's pixel at supersample 1 for OHS and R-OHS. There R* does not depend on
// the direction: its rows are kept as their twice-oversampled spectra (row_spectra.hpp), and a
// direction sums the 17 bins nearest ψ̄_x/λ of every row against the plane wave along y (the
// plain sum over the grid to ~1e-14 of Σ|R*|, its own rounding; ~25x faster). GHS, R-GHS and
// Kirchhoff sum the grid directly at the exact ξ3 = ψ·n of each direction, where the image
// interpolates between ξ3 nodes (within its phase_error).
// Its albedo is the image's disk sum at supersample 4 (the chirp-z transforms compute the same
// quadrature of eval as the BSDF's rule, bsdf.hpp, far faster than eval at each sub-pixel).
PointAnswers fft_point(const LobeQuery& query);
// The same for any footprint of the query's heightfield: the BSDF's point field (nothing to build
// over the whole field, each footprint's grids are made on first use).
PointAnswersAt fft_point_field(const LobeQuery& query);

// The method's images: the query's lobe (planned: supersampling resolved).
LobeImage fft_lobe(const LobeQuery& query);

// The options above, checked.
struct FftSettings {
    double step_um = 0.0;  // 0: chosen per wavelength and axis
    double window_sigmas = 4.0;
    double guard_widths = 6.0;
    double oversampling = 3.0;
    double phase_error = 0.01;
    bool truncate_at_edges = false;  // option edge=truncate on a non-periodic field
};
FftSettings fft_settings(const LobeQuery& query);

// The option list of every method built on these transforms.
std::vector<MethodOption> fft_options();

// The method-table entry: "fft", Yan 2018 eq. 6, brdf, the options above.
MethodEntry fft_method();

}  // namespace glintscope
