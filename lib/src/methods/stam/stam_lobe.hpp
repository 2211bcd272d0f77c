#pragma once
// Stam 1999 "Diffraction Shaders": the expected lobe of a surface known only statistically, a
// Gaussian random field (§4) or a periodic-like surface (§5: gratings, CD tracks), answering the
// same LobeQuery as the FFT ground truth. Where the FFT lobe transforms one footprint of one
// heightfield, this is the mean of that lobe over all footprints of surfaces with the same
// statistics (docs/stam.md).
#include <complex>
#include <string>
#include <vector>

#include "glintscope/generate/generate.hpp"
#include "glintscope/lobe/query.hpp"
#include "lobe/method.hpp"

namespace glintscope {

enum class StamSurfaceKind { gaussian, grating, cd };

// What the shader knows of the surface.
struct StamSurface {
    StamSurfaceKind kind = StamSurfaceKind::gaussian;
    GaussianFieldParameters gaussian;
    GratingParameters grating;
    CdParameters cd;
};

// The surface parameters of a query: method options first, then the heightfield's generator
// provenance, then (Gaussian fields only) its measured statistics. Throws Error naming the
// missing or bad parameter. `sources` receives, per parameter, where it came from
// ("stam.source.KEY" = generator, statistics, options or default).
StamSurface stam_surface(const LobeQuery& query, Provenance* sources = nullptr);

// |w̃(v)|²/A_c of the query's coherence window at spatial frequency v (µm⁻¹): the lobe of a
// flat mirror divided by ξ1.
double window_lobe(const Footprint& footprint, double vx, double vy);

// Stam 1999 eq. 14–15: S_p(v) = e^{−g} Σ_{m≥1} g^m/m! D_m(v), the spectral density (µm²) of
// p = e^{−i2π ξ3 H/λ} over a Gaussian random field, at spatial frequency v = ψ̄/λ (µm⁻¹).
double stam_spectral_density(const GaussianFieldParameters& surface, double g, double vx, double vy);

// The part of that series that depends on g alone (the Poisson weights over the bulk of m, and
// D_1,m's factors), made once where g is fixed (OHS, R-OHS: ξ3 = 2).
struct PoissonSeries {
    int first = 1;                              // the first m
    std::vector<double> weights;                // P_m = e^{−g} g^m/m!
    std::vector<double> c1_scale_over_m;        // π T_x T_y/m
    std::vector<double> minus_quarter_over_m;   // −1/(4m)
};
PoissonSeries poisson_series(const GaussianFieldParameters& surface, double g);
double stam_spectral_density(const GaussianFieldParameters& surface, const PoissonSeries& series, double vx, double vy);

// Φ(v) = ∫ (e^{−iκ b(s)} − 1) e^{−i2π v·s} ds of one CD bump centred at the origin
// (Stam 1999 eq. 24–25 as amplitudes), κ = 2π ξ3/λ the phase per µm of height.
std::complex<double> cd_bump_transform(const CdParameters& cd, double phase_per_height, double vx, double vy);

// J_m(z)²: the share of a sinusoidal grating's light in order m, z = 2π ξ3 A/λ.
double grating_efficiency(int order, double phase_amplitude);

LobeImage stam_lobe(const LobeQuery& query);

// The method-table entry: "stam", Stam 1999 eq. 14-16 and 21-25, brdf.
MethodEntry stam_method();

}  // namespace glintscope
