// One Gabor kernel and its Fourier transform (Yan 2018 §4.1–4.2), and the Gabor settings.
#include <cmath>
#include <numbers>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "gabor.hpp"

namespace glintscope {
namespace {


std::complex<double> unit_phasor(double radians) { return {std::cos(radians), std::sin(radians)}; }

}  // namespace

// Yan 2018 eq. 7, times the chirp e^{−iπ dᵀBd}.
std::complex<double> gabor_kernel_value(const GaborKernel& kernel, Point2 s_um) {
    const double dx = s_um.x - kernel.centre_um.x;
    const double dy = s_um.y - kernel.centre_um.y;
    const double variance = kernel.sigma_um * kernel.sigma_um;
    const double gaussian = std::exp(-(dx * dx + dy * dy) / (2.0 * variance)) / (2.0 * pi * variance);
    const Chirp& b = kernel.chirp;
    const double chirp_turns = 0.5 * (b.xx * dx * dx + 2.0 * b.xy * dx * dy + b.yy * dy * dy);
    return gaussian * unit_phasor(-2.0 * pi * (kernel.frequency.x * s_um.x + kernel.frequency.y * s_um.y + chirp_turns));
}

// Yan 2018 eq. 8 with the misprint corrected: shifting the Gaussian to μ multiplies its transform
// e^{−2π²σ²|v|²} by e^{−i2π μ·v}, and the plane wave e^{−i2π a·s} shifts v to v + a.
// The chirped form: with d = s − μ, F[g](v) = e^{−i2π μ·u} ∫ G_2D(d) e^{−iπ dᵀBd − i2π u·d} dd, and
// G_2D(d) e^{−iπ dᵀBd} = e^{−π dᵀA d}/(2πσ²) with A = (σ⁻² I + i2πB)/(2π), so Folland 1989 App. A
// Thm. 1 (∫ e^{−π xᵀAx − i2π u·x} dx = det(A)^{−1/2} e^{−π uᵀA⁻¹u}) gives
// det(M)^{−1/2} e^{−2π²σ² uᵀM⁻¹u} with M = 2πσ²A = I + i2πσ²B. M's eigenvalues 1 + iε_j have
// positive real parts, so the product of their principal roots, det(M)'s branch, is the principal
// root of det(M) (the arguments add up to less than π). B = 0 is Yan 2018 eq. 8.
std::complex<double> gabor_kernel_transform(const GaborKernel& kernel, Point2 v) {
    using Complex = std::complex<double>;
    const double ux = v.x + kernel.frequency.x;
    const double uy = v.y + kernel.frequency.y;
    const double sigma2 = kernel.sigma_um * kernel.sigma_um;
    const double e = 2.0 * pi * sigma2;
    const Complex mxx(1.0, e * kernel.chirp.xx), mxy(0.0, e * kernel.chirp.xy), myy(1.0, e * kernel.chirp.yy);
    const Complex det = mxx * myy - mxy * mxy;
    const Complex quadratic = (myy * ux * ux - 2.0 * mxy * ux * uy + mxx * uy * uy) / det;  // uᵀM⁻¹u
    return std::exp(-2.0 * pi * pi * sigma2 * quadratic) / std::sqrt(det) *
           unit_phasor(-2.0 * pi * (kernel.centre_um.x * ux + kernel.centre_um.y * uy));
}

// Yan 2018 eq. 14–15 (the cell's box replaced by a Gaussian of equal area, Yan 2018 eq. 13).
GaborCellKernel gabor_cell_kernel(Point2 centre_um, double cell_um, const SurfacePoint& surface_at_centre,
                                  double xi2, double xi3, double lambda_um) {
    const double hx = surface_at_centre.dh_dx;
    const double hy = surface_at_centre.dh_dy;
    const double alpha = surface_at_centre.height - (hx * centre_um.x + hy * centre_um.y);
    GaborCellKernel cell;
    cell.coefficient = cell_um * cell_um * xi2 * unit_phasor(-2.0 * pi * xi3 * alpha / lambda_um);
    cell.kernel = {centre_um, 0.5 * cell_um, {xi3 * hx / lambda_um, xi3 * hy / lambda_um}, {}};
    return cell;
}

GaborCellKernel gabor_cell_kernel(Point2 centre_um, double cell_um, const SurfacePoint& surface_at_centre,
                                  const SurfaceCurvature& curvature_at_centre, double xi2, double xi3,
                                  double lambda_um) {
    GaborCellKernel cell = gabor_cell_kernel(centre_um, cell_um, surface_at_centre, xi2, xi3, lambda_um);
    const double scale = xi3 / lambda_um;  // the phase ξ3 H/λ's second-order term, in turns
    cell.kernel.chirp = {scale * curvature_at_centre.d2h_dx2, scale * curvature_at_centre.d2h_dxdy,
                         scale * curvature_at_centre.d2h_dy2};
    return cell;
}

void validate(const GaborSettings& settings) {
    if (settings.kernels_per_texel < 1 || settings.kernels_per_texel > 16)
        throw Error("gabor: kernels_per_texel must be an integer from 1 to 16, got " +
                    std::to_string(settings.kernels_per_texel));
    if (!(settings.footprint_sigmas >= 1.0 && settings.footprint_sigmas <= 8.0))
        throw Error("gabor: footprint truncation must be 1 to 8 sigma, got " +
                    shortest_text(settings.footprint_sigmas));
    // exp_neg (gabor_math.hpp) is accurate for exponents up to 25 = 5².
    if (!(settings.kernel_sigmas >= 1.0 && settings.kernel_sigmas <= 5.0))
        throw Error("gabor: kernel truncation must be 1 to 5 sigma, got " + shortest_text(settings.kernel_sigmas));
    if (settings.order != 1 && settings.order != 2)
        throw Error("gabor: order must be 1 or 2, got " + std::to_string(settings.order));
}

GaborSettings gabor_settings(const LobeQuery& query) {
    GaborSettings settings;
    const double density = method_option_number(query, "kernels_per_texel", settings.kernels_per_texel);
    // The kernel grid must tile the periodic heightfield, so K is a whole number.
    if (density != std::floor(density) || density < 1.0 || density > 16.0)
        throw Error("option kernels_per_texel='" + query.method_options.at("kernels_per_texel") +
                    "' must be an integer from 1 to 16");
    settings.kernels_per_texel = static_cast<int>(density);
    settings.footprint_sigmas = method_option_number(query, "footprint_truncation", settings.footprint_sigmas);
    settings.kernel_sigmas = method_option_number(query, "kernel_truncation", settings.kernel_sigmas);
    const double order = method_option_number(query, "order", settings.order);
    if (order != 1.0 && order != 2.0)
        throw Error("option order='" + query.method_options.at("order") + "' must be 1 or 2");
    settings.order = static_cast<int>(order);
    validate(settings);
    return settings;
}

}  // namespace glintscope
