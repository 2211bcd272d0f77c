// Stam 1999 "Diffraction Shaders" as a lobe method.
//
// The FFT lobe of one footprint is f_r = ξ1/A_c |R̃(v)|², R̃(v) = ∫ w(s) ξ2 p(s) e^{−i2π v·s} ds,
// p = e^{−i2π ξ3 H/λ}, v = ψ̄/λ (Yan 2018 eq. 3, 6). Stam replaces the one surface by its
// statistics: ⟨|R̃|²⟩ = |⟨p⟩|²|w̃(v)|² + ∫ (w⋆w)(τ) C_p(τ) e^{−i2π v·τ} dτ (Stam 1999 eq. 11), and
// when the footprint is much wider than the correlation length T (σ_c ≫ T), w⋆w ≈ A_c over the
// support of C_p, so f_r = ξ1 (e^{−g} |w̃(v)|²/A_c + S_p(v)) with ⟨p⟩ = e^{−g/2} (Stam 1999 eq. 12).
// Stam's infinite patch has δ(u, v) in place of |w̃|²/A_c; here the coherent part is drawn as the
// footprint's own window transform, exactly as the FFT lobe draws a flat mirror, times e^{−g}.
//
// Diffraction model (docs/stam.md): Stam's field (Stam 1999 eq. 2, 6–8) is the Kirchhoff integral with the
// slope term integrated by parts, ∫ (ψ·m) e^{…} ds = (|ψ|²/ψ·n) ∫ e^{…} ds over the whole plane,
// and his factor F² G/w² (Stam 1999 eq. 9–10) with G = (1 − k̂1·k̂2)²/(cos θ1 cos θ2), k̂1 = −ω_i, k̂2 = ω_o,
// w = −ψ·n, equals |ψ|⁴/(4 cos θ_i cos θ_o (ψ·n)²): that is Yan 2018 Fig. 6's Kirchhoff model,
// ξ1 = F (ψ·n)²/(4λ² cos θ_i cos θ_o), ξ3 = ψ·n, with ξ2 replaced by its integrated-by-parts
// value |ψ|²/(ψ·n)². The statistics (Stam 1999 eq. 11–16) only need ξ2 independent of H, so every model of
// Fig. 6 is honoured: OHS, GHS, R-OHS, R-GHS with their own ξ1, ξ3 and ξ2 = 1, Kirchhoff as Stam.
// F is applied once (the reflectance), where Stam's F² squares his amplitude-like F.
#include "methods/stam/stam_lobe.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/surface/statistics.hpp"

// The SIMD helpers are inlined into the SIMD sum; no vector type crosses a call, so -Wpsabi's
// note does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace glintscope {
namespace {


// Stam's formula wants the footprint much wider than the surface's correlation scale; below this
// ratio the image metadata carries a warning.
constexpr double kWideFootprintRatio = 3.0;

// sin(t)/t.
double sinc(double t) { return std::fabs(t) < 1e-8 ? 1.0 - t * t / 6.0 : std::sin(t) / t; }

const char* correlation_name(CorrelationFunction correlation) {
    switch (correlation) {
        case CorrelationFunction::c1: return "c1";
        case CorrelationFunction::c2: return "c2";
        case CorrelationFunction::c3: return "c3";
    }
    return "c1";
}

const char* kind_name(StamSurfaceKind kind) {
    switch (kind) {
        case StamSurfaceKind::gaussian: return "gaussian";
        case StamSurfaceKind::grating: return "grating";
        case StamSurfaceKind::cd: return "cd";
    }
    return "gaussian";
}

// The generator recipe recorded in a heightfield's provenance (generate.hpp: "generator",
// "generator.preset", "generator.KEY_UNIT"), or an empty kind when there is none.
Recipe recorded_recipe(const Provenance& provenance) {
    Recipe recipe;
    recipe.kind.clear();
    const auto generator = provenance.find("generator");
    if (generator == provenance.end()) return recipe;
    const auto preset = provenance.find("generator.preset");
    const std::string kind = preset != provenance.end() ? preset->second : generator->second;
    const std::vector<std::string> kinds = generator_kinds();
    if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) return recipe;
    recipe = default_recipe(kind);
    for (const RecipeKey& key : recipe_keys()) {
        if (std::find(key.kinds.begin(), key.kinds.end(), kind) == key.kinds.end()) continue;
        const auto value = provenance.find("generator." + key.name + (key.unit.empty() ? "" : "_" + key.unit));
        if (value != provenance.end()) set_recipe_value(recipe, key.name, value->second);
    }
    return recipe;
}

StamSurfaceKind surface_kind(const LobeQuery& query, const Recipe& recipe) {
    const auto option = query.method_options.find("surface");
    if (option == query.method_options.end()) {
        if (recipe.kind == "grating") return StamSurfaceKind::grating;
        if (recipe.kind == "cd") return StamSurfaceKind::cd;
        return StamSurfaceKind::gaussian;
    }
    for (StamSurfaceKind kind : {StamSurfaceKind::gaussian, StamSurfaceKind::grating, StamSurfaceKind::cd})
        if (option->second == kind_name(kind)) return kind;
    throw Error("option surface must be gaussian, grating or cd, got '" + option->second + "'");
}

bool is_gaussian_recipe(const Recipe& recipe) { return recipe.kind == "gaussian" || recipe.kind == "isotropic" || recipe.kind == "brushed"; }

// A positive length option overriding `value`, with its source recorded.
void override_length(const LobeQuery& query, const std::string& key, double& value, std::string& source) {
    if (!query.method_options.count(key)) return;
    value = method_option_length_um(query, key, 0.0);
    if (!(value > 0.0) || !std::isfinite(value))
        throw Error("option " + key + " must be a positive length, got '" + query.method_options.at(key) + "'");
    source = "options";
}

GaussianFieldParameters gaussian_parameters(const LobeQuery& query, const Recipe& recipe, Provenance& sources) {
    GaussianFieldParameters surface;
    std::string height_source, length_source, correlation_source = "default";
    if (is_gaussian_recipe(recipe)) {
        surface = recipe.gaussian;
        height_source = length_source = correlation_source = "generator";
    }
    const bool need_statistics = height_source.empty() && (!query.method_options.count("sigma_h") ||
                                                           !query.method_options.count("correlation_length"));
    if (need_statistics) {
        // Measured Sq and the 1/e autocorrelation lengths (statistics.hpp: T of C1, C2, C3).
        const SurfaceStatistics statistics = compute_statistics(*query.field);
        surface.sigma_h_um = statistics.sq_um;
        surface.correlation_length_x_um = statistics.correlation_length_x_um;
        surface.correlation_length_y_um = statistics.correlation_length_y_um;
        surface.orientation_rad = 0.0;
        height_source = length_source = "statistics";
    }
    override_length(query, "sigma_h", surface.sigma_h_um, height_source);
    override_length(query, "correlation_length", surface.correlation_length_x_um, length_source);
    if (length_source == "options") surface.correlation_length_y_um = surface.correlation_length_x_um;
    if (const auto option = query.method_options.find("correlation"); option != query.method_options.end()) {
        const std::string& name = option->second;
        if (name == "c1") surface.correlation = CorrelationFunction::c1;
        else if (name == "c2") surface.correlation = CorrelationFunction::c2;
        else if (name == "c3") surface.correlation = CorrelationFunction::c3;
        else throw Error("option correlation must be c1, c2 or c3, got '" + name + "'");
        correlation_source = "options";
    }
    if (!(surface.correlation_length_x_um > 0.0) || !(surface.correlation_length_y_um > 0.0))
        throw Error("stam: the heightfield's correlation length could not be measured; give option correlation_length");
    if (!(surface.sigma_h_um >= 0.0)) throw Error("stam: the heightfield's rms height is undefined; give option sigma_h");
    sources["stam.source.sigma_h"] = height_source;
    sources["stam.source.correlation_length"] = length_source;
    sources["stam.source.correlation"] = correlation_source;
    return surface;
}

GratingParameters grating_parameters(const LobeQuery& query, const Recipe& recipe, Provenance& sources) {
    GratingParameters grating;
    std::string source;
    if (recipe.kind == "grating") {
        grating = recipe.grating;
        source = "generator";
    } else if (!query.method_options.count("period") || !query.method_options.count("amplitude")) {
        throw Error("stam: surface=grating on a heightfield not made by the grating generator needs options period and amplitude");
    }
    std::string period_source = source, amplitude_source = source;
    override_length(query, "period", grating.period_um, period_source);
    override_length(query, "amplitude", grating.amplitude_um, amplitude_source);
    sources["stam.source.period"] = period_source;
    sources["stam.source.amplitude"] = amplitude_source;
    return grating;
}

// ---- Gaussian random fields (Stam 1999 §4) -------------------------------------------------

// D_m, the transform of C^m (Stam 1999 eq. 15), with U² = (2π T_x v_u)², V² = (2π T_y v_v)² in
// the field's own axes (T_x along `orientation`). Each is at most π T_x T_y or 4 T_x T_y, so the
// terms of the series never overflow once their Poisson weights are formed stably.
double correlation_power_transform(CorrelationFunction correlation, double tx, double ty, int m, double u2,
                                   double v2) {
    const double mm = m;
    switch (correlation) {
        case CorrelationFunction::c1: return pi * tx * ty / mm * std::exp(-(u2 + v2) / (4.0 * mm));  // Stam 1999 eq. 15, D_1,m
        case CorrelationFunction::c2: {
            const double s = mm * mm + u2 + v2;
            return 2.0 * pi * tx * ty * mm / (s * std::sqrt(s));  // D_2,m
        }
        case CorrelationFunction::c3: return 2.0 * tx * mm / (mm * mm + u2) * (2.0 * ty * mm / (mm * mm + v2));  // D_3,m
    }
    return 0.0;
}

}  // namespace

StamSurface stam_surface(const LobeQuery& query, Provenance* sources) {
    Provenance recorded;
    const Recipe recipe = recorded_recipe(query.field->provenance);
    StamSurface surface;
    surface.kind = surface_kind(query, recipe);
    switch (surface.kind) {
        case StamSurfaceKind::gaussian: surface.gaussian = gaussian_parameters(query, recipe, recorded); break;
        case StamSurfaceKind::grating: surface.grating = grating_parameters(query, recipe, recorded); break;
        case StamSurfaceKind::cd:
            if (recipe.kind != "cd") throw Error("stam: surface=cd needs a heightfield made by the cd generator");
            surface.cd = recipe.cd;
            recorded["stam.source.cd"] = "generator";
            break;
    }
    if (sources) *sources = recorded;
    return surface;
}

double window_lobe(const Footprint& footprint, double vx, double vy) {
    if (footprint.shape == FootprintShape::box) {
        // w̃ = a b sinc(π a v_x) sinc(π b v_y), A_c = a b (sides a along x, b along y).
        const double a = box_width_um(footprint), b = box_height_um(footprint);
        const double amplitude = sinc(pi * a * vx) * sinc(pi * b * vy);
        return a * b * amplitude * amplitude;
    }
    // w̃ = 2πσ² e^{−2π²σ²|v|²}, A_c = πσ²: |w̃|²/A_c = 4πσ² e^{−4π²σ²|v|²}.
    const double sigma = footprint.sigma_um;
    return 4.0 * pi * sigma * sigma * std::exp(-4.0 * pi * pi * sigma * sigma * (vx * vx + vy * vy));
}

namespace {

using Double4 = double __attribute__((vector_size(32)));
using Bits4 = unsigned long long __attribute__((vector_size(32)));

inline __attribute__((always_inline)) Double4 load4(const double* p) {
    Double4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

// e^x for x ≤ 0 in four lanes, to about 1 ulp like std::exp (which, one call per lane, costs
// most of a Gaussian field's series): x = k ln 2 + r with |r| ≤ ln2/2, e^r by its Taylor
// polynomial of degree 13 (remainder < 1e-17), 2^k put into the exponent bits; e^x below the
// smallest normal double (x < −708) is 0.
inline __attribute__((always_inline)) Double4 exp_nonpositive4(Double4 x) {
    const Double4 underflow = {-708.0, -708.0, -708.0, -708.0};
    const Bits4 normal = (Bits4)(x >= underflow);
    x = x < underflow ? underflow : x;
    constexpr double shifter = 0x1.8p52;  // adding it rounds to an integer held in the low mantissa bits
    const Double4 shifted = x * 1.4426950408889634 + shifter;
    const Double4 k = shifted - shifter;
    const Double4 r = (x - k * 6.93147180369123816490e-01) - k * 1.90821492927058770002e-10;  // ln 2, hi + lo
    Double4 p = r * (1.0 / 6227020800.0) + 1.0 / 479001600.0;
    for (const double c : {1.0 / 39916800.0, 1.0 / 3628800.0, 1.0 / 362880.0, 1.0 / 40320.0, 1.0 / 5040.0, 1.0 / 720.0,
                           1.0 / 120.0, 1.0 / 24.0, 1.0 / 6.0, 0.5, 1.0, 1.0})
        p = p * r + c;
    const Bits4 bits = ((Bits4)shifted + 1023) << 52;  // (k + 1023) in the exponent field
    return (Double4)((Bits4)(p * (Double4)bits) & normal);
}

// Σ_m P_m π T_x T_y/m e^{−(U² + V²)/(4m)}, D_1,m of Stam 1999 eq. 15, four terms per SIMD step
// (the rest one by one), with the partial sums added in a fixed order.
inline __attribute__((always_inline)) double c1_series_in_lanes(const double* weights, const double* scale_over_m,
                                                                const double* minus_quarter_over_m, int n,
                                                                double u2_plus_v2) {
    Double4 sum4 = {0.0, 0.0, 0.0, 0.0};
    int j = 0;
    for (; j + 4 <= n; j += 4)
        sum4 += load4(weights + j) * load4(scale_over_m + j) * exp_nonpositive4(u2_plus_v2 * load4(minus_quarter_over_m + j));
    double sum = 0.0;
    for (; j < n; ++j) sum += weights[j] * scale_over_m[j] * std::exp(u2_plus_v2 * minus_quarter_over_m[j]);
    return ((sum4[0] + sum4[1]) + (sum4[2] + sum4[3])) + sum;
}

// c1_series_in_lanes compiled for AVX2 and without. Its vector helpers are called from the inlined
// body, not from the clone itself: Clang 14 refuses a 256-bit vector passed by value from the AVX2
// clone to a helper compiled without AVX, even one that is always inlined.
__attribute__((target_clones("arch=x86-64-v3", "default")))
double c1_series(const double* weights, const double* scale_over_m, const double* minus_quarter_over_m, int n,
                 double u2_plus_v2) {
    return c1_series_in_lanes(weights, scale_over_m, minus_quarter_over_m, n, u2_plus_v2);
}

}  // namespace

PoissonSeries poisson_series(const GaussianFieldParameters& surface, double g) {
    PoissonSeries series;
    if (!(g > 0.0)) return series;
    // Stam 1999 eq. 14: Σ_m P_m D_m with Poisson(g) weights P_m = e^{−g} g^m/m!. g^m and m! overflow
    // separately for large g, but P_m ≤ 1: the first weight of the Poisson bulk g ± (10√g + 10) is
    // formed in log space and the others by P_{m+1} = P_m g/(m + 1); outside the bulk the weights
    // are below e^{−50} of the largest, and every D_m is bounded by D_1(0).
    const double spread = 10.0 * std::sqrt(g) + 10.0;
    series.first = std::max(1, static_cast<int>(std::floor(g - spread)));
    const int last = static_cast<int>(std::ceil(g + spread));
    double weight = std::exp(-g + series.first * std::log(g) - std::lgamma(series.first + 1.0));
    const double c1_scale = pi * surface.correlation_length_x_um * surface.correlation_length_y_um;
    for (int m = series.first; m <= last; ++m) {
        series.weights.push_back(weight);
        series.c1_scale_over_m.push_back(c1_scale / m);
        series.minus_quarter_over_m.push_back(-0.25 / m);
        weight *= g / (m + 1);
    }
    return series;
}

double stam_spectral_density(const GaussianFieldParameters& surface, const PoissonSeries& series, double vx, double vy) {
    if (series.weights.empty()) return 0.0;
    const double c = std::cos(surface.orientation_rad), s = std::sin(surface.orientation_rad);
    const double tx = surface.correlation_length_x_um, ty = surface.correlation_length_y_um;
    const double big_u = 2.0 * pi * tx * (c * vx + s * vy);   // Stam 1999 eq. 15: U = k u T_x
    const double big_v = 2.0 * pi * ty * (-s * vx + c * vy);  // V = k v T_y
    const double u2 = big_u * big_u, v2 = big_v * big_v;
    const int count = static_cast<int>(series.weights.size());
    if (surface.correlation == CorrelationFunction::c1)
        return c1_series(series.weights.data(), series.c1_scale_over_m.data(), series.minus_quarter_over_m.data(), count,
                         u2 + v2);
    double sum = 0.0;
    for (int k = 0; k < count; ++k)
        sum += series.weights[k] * correlation_power_transform(surface.correlation, tx, ty, series.first + k, u2, v2);
    return sum;
}

double stam_spectral_density(const GaussianFieldParameters& surface, double g, double vx, double vy) {
    return stam_spectral_density(surface, poisson_series(surface, g), vx, vy);
}

std::complex<double> cd_bump_transform(const CdParameters& cd, double phase_per_height, double vx, double vy) {
    const double a = cd.bump_width_um, b = cd.bump_length_um;
    const double phase = phase_per_height * cd.bump_height_um;  // k w h0 of Stam 1999 eq. 24–25
    const double along = b * sinc(pi * b * vy);
    if (cd.shape == BumpShape::flat)
        // Φ⁰ = (e^{−iκh0} − 1) a sinc(π a v_x) · b sinc(π b v_y) (Stam 1999 eq. 24).
        return (std::polar(1.0, -phase) - 1.0) * a * sinc(pi * a * vx) * along;
    // Φ¹ = a e^{−iκh0/2} sinc((κh0 + 2π a v_x)/2) − a sinc(π a v_x), times b sinc(π b v_y) (Stam 1999 eq. 25).
    return (a * std::polar(1.0, -0.5 * phase) * sinc(0.5 * (phase + 2.0 * pi * a * vx)) - a * sinc(pi * a * vx)) *
           along;
}

double grating_efficiency(int order, double phase_amplitude) {
    // Jacobi–Anger: e^{−iz sin φ} = Σ_m J_m(z) e^{−imφ}, so order m carries J_m(z)² (J_−m² = J_m²).
    const double j = std::cyl_bessel_j(static_cast<double>(std::abs(order)), phase_amplitude);
    return j * j;
}

namespace {

// Everything one wavelength's pixels share.
struct Evaluation {
    const LobeQuery* query = nullptr;
    const StamSurface* surface = nullptr;
    double lambda_um = 0.0;
    bool has_material = false;
    ComplexIndex eta;
    // A Gaussian field's series when ξ3, and so g, is the same for every direction.
    bool fixed_series = false;
    PoissonSeries series;
};

// The orders m of spacing 1/period along a unit direction whose window transform can reach v:
// all of them for a box (sinc² tails), those within 1.2/σ_c (|w̃|² < e^{−56}) for a Gaussian.
struct OrderRange {
    int first = 0;
    int last = -1;
};

OrderRange orders_near(const Footprint& footprint, double lambda_um, double period_um, double v_along) {
    const double reach = footprint.shape == FootprintShape::box ? 3.0 / lambda_um : 1.2 / footprint.sigma_um;
    return {static_cast<int>(std::ceil((-v_along - reach) * period_um)),
            static_cast<int>(std::floor((-v_along + reach) * period_um))};
}

// ⟨|R̃|²⟩/A_c for a Gaussian random field: e^{−g}|w̃|²/A_c + S_p, g = (2π ξ3 σ_h/λ)²
// (Stam 1999 eq. 12–16 with k w → 2π ξ3/λ).
double gaussian_intensity(const Evaluation& e, double xi3_value, double vx, double vy) {
    const GaussianFieldParameters& surface = e.surface->gaussian;
    const double root_g = 2.0 * pi * xi3_value * surface.sigma_h_um / e.lambda_um;
    const double g = root_g * root_g;  // Stam 1999 §4: g = (k w σ_h)²
    const double scattered = e.fixed_series ? stam_spectral_density(surface, e.series, vx, vy)
                                            : stam_spectral_density(surface, g, vx, vy);
    return std::exp(-g) * window_lobe(e.query->footprint, vx, vy) + scattered;
}

// A sinusoidal grating H = A sin(2π u/Λ): order m at v = −m ê/Λ with efficiency J_m(2π ξ3 A/λ)²
// (Stam 1999 eq. 23, 26 for a periodic profile), each drawn as the window's transform; orders are
// summed incoherently, which needs σ_c ≫ Λ.
double grating_intensity(const Evaluation& e, double xi3_value, double vx, double vy) {
    const GratingParameters& grating = e.surface->grating;
    const double ex = std::cos(grating.angle_rad), ey = std::sin(grating.angle_rad);
    const double z = 2.0 * pi * xi3_value * grating.amplitude_um / e.lambda_um;
    const OrderRange range = orders_near(e.query->footprint, e.lambda_um, grating.period_um, ex * vx + ey * vy);
    double sum = 0.0;
    for (int m = range.first; m <= range.last; ++m)
        sum += grating_efficiency(m, z) *
               window_lobe(e.query->footprint, vx + m * ex / grating.period_um, vy + m * ey / grating.period_um);
    return sum;
}

// CD tracks along y at x_n = (n + 1/2)Δx with Poisson bumps of density ν_y per track, to first
// order in the bumps as Stam 1999 eq. 21 (p = 1 + Σ φ): the mean field is
// w̃(v) + (ν_y/Δx) Φ(v) Σ_m ± w̃(v − m x̂/Δx) (Poisson summation over the tracks, Stam 1999 eq. 22),
// so order 0 carries |1 + ν_y Φ/Δx|² and order m ≠ 0 carries |ν_y Φ/Δx|²; the Poisson scatter adds
// ν_y |Φ(v)|²/Δx per unit area. The generator draws each track's bumps independently, so this
// scatter spreads over all v_x; Stam 1999 eq. 23 shares the y_m between tracks and gets lines instead.
double cd_intensity(const Evaluation& e, double xi3_value, double vx, double vy) {
    const CdParameters& cd = e.surface->cd;
    const double per_area = cd.bump_density_per_um / cd.track_spacing_um;
    const std::complex<double> bump = per_area * cd_bump_transform(cd, 2.0 * pi * xi3_value / e.lambda_um, vx, vy);
    const OrderRange range = orders_near(e.query->footprint, e.lambda_um, cd.track_spacing_um, -vx);
    double sum = 0.0;
    for (int m = range.first; m <= range.last; ++m) {
        const double amplitude2 = std::norm(m == 0 ? 1.0 + bump : bump);
        sum += amplitude2 * window_lobe(e.query->footprint, vx - m / cd.track_spacing_um, vy);
    }
    return sum + std::norm(bump) / per_area;
}

// f_r at one outgoing direction: ξ1 (Yan 2018 Fig. 6, with F at cos θ_d = |ψ|/2 as the FFT lobe)
// times ⟨|R̃(ψ̄/λ)|²⟩/A_c of the surface statistics.
double stam_value(const Evaluation& e, Vec3 omega_i, Vec3 omega_o) {
    const LobeQuery& query = *e.query;
    const Vec3 psi = omega_i + omega_o;
    const double vx = psi.x / e.lambda_um, vy = psi.y / e.lambda_um;
    const double xi3_value = xi3(query.model, omega_i, omega_o);
    const double fresnel = e.has_material ? fresnel_conductor(e.eta, 0.5 * length(psi)) : 1.0;
    double xi1 = xi1_geometric(query.model, omega_i, omega_o) * fresnel / (e.lambda_um * e.lambda_um);
    if (query.model == DiffractionModel::kirchhoff) {
        // Stam 1999 eq. 6–8: ξ2 = 1 − ψ̄·H'/(ψ·n) integrated by parts becomes |ψ|²/(ψ·n)².
        const double by_parts = dot(psi, psi) / (psi.z * psi.z);
        xi1 *= by_parts * by_parts;
    }
    switch (e.surface->kind) {
        case StamSurfaceKind::gaussian: return xi1 * gaussian_intensity(e, xi3_value, vx, vy);
        case StamSurfaceKind::grating: return xi1 * grating_intensity(e, xi3_value, vx, vy);
        case StamSurfaceKind::cd: return xi1 * cd_intensity(e, xi3_value, vx, vy);
    }
    return 0.0;
}


void fill_layer(const Evaluation& e, LobeImage& image, std::size_t layer) {
    fill_by_direction(image, layer, e.query->supersample,
                      [&](DiskPoint p) { return stam_value(e, e.query->omega_i, direction_from_disk(p.x, p.y)); });
}

// The footprint's linear size for the σ_c ≫ T comparison: σ_c, or half a box's shorter side.
double footprint_scale(const Footprint& footprint) {
    return footprint.shape == FootprintShape::box
               ? 0.5 * std::min(box_width_um(footprint), box_height_um(footprint))
               : footprint.sigma_um;
}

// Stam's statistics assume many correlation cells (or periods) inside the footprint.
std::string wide_footprint_warning(const Footprint& footprint, double scale_um, const std::string& what) {
    const double size = footprint_scale(footprint);
    if (size >= kWideFootprintRatio * scale_um) return "";
    return "footprint " + shortest_text(size) + " um < " + shortest_text(kWideFootprintRatio) + " x " + what + " " +
           shortest_text(scale_um) + " um: Stam's formula assumes a footprint much wider than the surface's " +
           "correlation scale";
}

// What Stam's formulas do not hold for here (the images' "stam.warning", the point answers'
// warning): a footprint not much wider than the surface's correlation scale, overlapping CD bumps.
std::string surface_warning(const StamSurface& surface, const Footprint& footprint) {
    switch (surface.kind) {
        case StamSurfaceKind::gaussian: {
            const GaussianFieldParameters& g = surface.gaussian;
            return wide_footprint_warning(footprint, std::max(g.correlation_length_x_um, g.correlation_length_y_um),
                                          "correlation length T");
        }
        case StamSurfaceKind::grating:
            return wide_footprint_warning(footprint, surface.grating.period_um, "period");
        case StamSurfaceKind::cd: {
            const CdParameters& cd = surface.cd;
            std::string warning = wide_footprint_warning(footprint, cd.track_spacing_um, "track spacing");
            // Stam 1999 eq. 21 keeps the bumps to first order: overlapping bumps (ν_y b of them per bump) are not.
            if (cd.bump_density_per_um * cd.bump_length_um > 0.1)
                warning += std::string(warning.empty() ? "" : "; ") + "bumps overlap (density x length " +
                           shortest_text(cd.bump_density_per_um * cd.bump_length_um) +
                           " > 0.1): Stam 1999 eq. 21 treats them to first order";
            return warning;
        }
    }
    return "";
}

void record_surface(const StamSurface& surface, const Footprint& footprint, LobeImage& image) {
    Provenance& m = image.metadata;
    m["stam.surface"] = kind_name(surface.kind);
    switch (surface.kind) {
        case StamSurfaceKind::gaussian: {
            const GaussianFieldParameters& g = surface.gaussian;
            m["stam.correlation"] = correlation_name(g.correlation);
            m["stam.sigma_h_um"] = shortest_text(g.sigma_h_um);
            m["stam.correlation_length_x_um"] = shortest_text(g.correlation_length_x_um);
            m["stam.correlation_length_y_um"] = shortest_text(g.correlation_length_y_um);
            m["stam.orientation_deg"] = shortest_text(g.orientation_rad * 180.0 / pi);
            break;
        }
        case StamSurfaceKind::grating:
            m["stam.period_um"] = shortest_text(surface.grating.period_um);
            m["stam.amplitude_um"] = shortest_text(surface.grating.amplitude_um);
            m["stam.angle_deg"] = shortest_text(surface.grating.angle_rad * 180.0 / pi);
            break;
        case StamSurfaceKind::cd: {
            const CdParameters& cd = surface.cd;
            m["stam.bump_height_um"] = shortest_text(cd.bump_height_um);
            m["stam.bump_width_um"] = shortest_text(cd.bump_width_um);
            m["stam.bump_length_um"] = shortest_text(cd.bump_length_um);
            m["stam.track_spacing_um"] = shortest_text(cd.track_spacing_um);
            m["stam.bump_density_per_um"] = shortest_text(cd.bump_density_per_um);
            m["stam.bump_shape"] = cd.shape == BumpShape::flat ? "flat" : "ramp";
            break;
        }
    }
    if (std::string warning = surface_warning(surface, footprint); !warning.empty()) m["stam.warning"] = std::move(warning);
}

// One evaluation per wavelength of the query; `query` and `surface` must outlive them.
std::vector<Evaluation> evaluations(const LobeQuery& query, const StamSurface& surface) {
    std::vector<Evaluation> all;
    for (double lambda : query.wavelengths_um) {
        Evaluation e;
        e.query = &query;
        e.surface = &surface;
        e.lambda_um = lambda;
        e.has_material = !query.material.name.empty();
        if (e.has_material) e.eta = complex_refractive_index(query.material.name, e.lambda_um);
        if (surface.kind == StamSurfaceKind::gaussian && !phase_depends_on_outgoing(query.model)) {
            const double root_g = 2.0 * pi * 2.0 * surface.gaussian.sigma_h_um / lambda;  // ξ3 = 2 (Yan 2018 Fig. 6)
            e.fixed_series = true;
            e.series = poisson_series(surface.gaussian, root_g * root_g);
        }
        all.push_back(e);
    }
    return all;
}

// The closed form per direction, with the query and surface it reads kept alive.
struct StamPoint {
    LobeQuery query;
    StamSurface surface;
    std::vector<Evaluation> per_wavelength;
};

PointAnswers stam_point(const LobeQuery& query) {
    auto point = std::make_shared<StamPoint>();
    point->query = query;
    point->surface = stam_surface(query);
    point->per_wavelength = evaluations(point->query, point->surface);
    std::shared_ptr<const StamPoint> shared = point;
    PointAnswers answers;
    answers.eval = [shared](Vec3 omega_i, Vec3 omega_o) {
        std::vector<double> f;
        for (const Evaluation& e : shared->per_wavelength) f.push_back(stam_value(e, omega_i, omega_o));
        return f;
    };
    answers.warning = surface_warning(point->surface, query.footprint);
    return answers;
}

}  // namespace

LobeImage stam_lobe(const LobeQuery& query) {
    Provenance sources;
    const StamSurface surface = stam_surface(query, &sources);
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    const std::vector<Evaluation> per_wavelength = evaluations(query, surface);
    for (std::size_t layer = 0; layer < per_wavelength.size(); ++layer) fill_layer(per_wavelength[layer], image, layer);
    record_surface(surface, query.footprint, image);
    image.metadata.insert(sources.begin(), sources.end());
    image.metadata["stam.model"] = to_string(query.model) + (query.model == DiffractionModel::kirchhoff
                                                                 ? " (Stam's own: slope term integrated by parts)"
                                                                 : " (xi2 = 1)");
    return image;
}

MethodEntry stam_method() {
    return {{"stam",
             "expected lobe of a statistically described surface: Gaussian random fields, gratings, CD tracks",
             "Stam 1999 eq. 14-16, 21-25",
             {Quantity::brdf},
             {},
             {{"surface", "gaussian, grating or cd (default: from the heightfield's generator, else gaussian)"},
              {"sigma_h", "rms height, a length (default: the generator's, else measured Sq)"},
              {"correlation_length", "correlation length T for both axes (default: the generator's, else measured)"},
              {"correlation", "c1, c2 or c3 (Stam 1999 eq. 14-16; default: the generator's, else c1)"},
              {"period", "grating period, a length (default: the generator's)"},
              {"amplitude", "grating amplitude A, a length (default: the generator's)"}},
             true},
            stam_lobe,
            stam_point};
}

}  // namespace glintscope
