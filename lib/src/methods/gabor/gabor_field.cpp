#include "gabor_field.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <vector>

#include "glintscope/core/parallel.hpp"

namespace glintscope::gabor {
namespace {

using Complex = std::complex<double>;

constexpr int kBandRows = 16;  // grid rows per parallel band

// One axis of a kernel's splat: grid indices [first, first + count) within kSplatSigmas σ of m.
struct AxisSpan {
    int first = 0;
    int count = 0;
};

AxisSpan axis_span(const SampleAxis& axis, double m, double sigma) {
    const double reach = kSplatSigmas * sigma;
    const int first = std::max(0, static_cast<int>(std::ceil((m - reach - axis.first_um) / axis.step_um)));
    const int last = std::min(axis.count - 1, static_cast<int>(std::floor((m + reach - axis.first_um) / axis.step_um)));
    return {first, std::max(0, last - first + 1)};
}

// What does not change from one ξ3 node to the next on a grid: every kernel's spans, its Gaussian
// factors e^{−d²/(2σ²)} along both axes (offsets into `gauss`), and the kernels reaching each band
// of grid rows, in kernel order (so every grid point sums its kernels in one order, whatever the
// thread count).
struct SplatPlan {
    int nx = 0, ny = 0;
    double x_first = 0.0, y_first = 0.0, x_step = 0.0, y_step = 0.0;
    std::vector<AxisSpan> x_span, y_span;
    std::vector<std::size_t> x_offset, y_offset;
    std::vector<double> gauss;
    std::vector<double> phased_re, phased_im;  // the factors at the current ξ3, laid out as gauss
    std::vector<std::vector<std::size_t>> by_band;

    bool fits(const FootprintSamples& s) const {
        return nx == s.x.count && ny == s.y.count && x_first == s.x.first_um && y_first == s.y.first_um &&
               x_step == s.x.step_um && y_step == s.y.step_um;
    }
};

void add_gaussian(const SampleAxis& axis, AxisSpan span, double m, double sigma, std::vector<double>& gauss) {
    for (int j = span.first; j < span.first + span.count; ++j) {
        const double d = axis.first_um + j * axis.step_um - m;
        gauss.push_back(std::exp(-d * d / (2.0 * sigma * sigma)));
    }
}

SplatPlan plan_splat(const KernelArrays& kernels, const FootprintSamples& samples, Point2 centre, double sigma) {
    SplatPlan plan;
    plan.nx = samples.x.count;
    plan.ny = samples.y.count;
    plan.x_first = samples.x.first_um;
    plan.y_first = samples.y.first_um;
    plan.x_step = samples.x.step_um;
    plan.y_step = samples.y.step_um;
    plan.by_band.resize((plan.ny + kBandRows - 1) / kBandRows);
    for (std::size_t k = 0; k < kernels.size(); ++k) {
        const double mx = centre.x + kernels.px[k], my = centre.y + kernels.py[k];
        const AxisSpan sx = axis_span(samples.x, mx, sigma), sy = axis_span(samples.y, my, sigma);
        plan.x_span.push_back(sx);
        plan.y_span.push_back(sy);
        plan.x_offset.push_back(plan.gauss.size());
        add_gaussian(samples.x, sx, mx, sigma, plan.gauss);
        plan.y_offset.push_back(plan.gauss.size());
        add_gaussian(samples.y, sy, my, sigma, plan.gauss);
        if (sx.count == 0 || sy.count == 0) continue;
        for (int band = sy.first / kBandRows; band <= (sy.first + sy.count - 1) / kBandRows; ++band)
            plan.by_band[band].push_back(k);
    }
    return plan;
}

// e^{−i2π t} with t reduced to [−½, ½] first, so that large phases keep their accuracy.
Complex unit_phasor(double turns) {
    const double reduced = turns - std::nearbyint(turns);
    return {std::cos(2.0 * pi * reduced), -std::sin(2.0 * pi * reduced)};
}

// factors[j] = scale · gauss[j] e^{−i2π f (s_j − m)} over a span, the phase stepped by one
// multiplication.
void phase_factors(const SampleAxis& axis, AxisSpan span, const double* gauss, double m, double frequency,
                   Complex scale, double* re, double* im) {
    const double d0 = axis.first_um + span.first * axis.step_um - m;
    const Complex start = scale * unit_phasor(frequency * d0);
    double c = start.real(), s = start.imag();
    const Complex step = unit_phasor(frequency * axis.step_um);
    const double step_c = step.real(), step_s = step.imag();
    for (int j = 0; j < span.count; ++j) {
        re[j] = gauss[j] * c;
        im[j] = gauss[j] * s;
        const double next = c * step_c - s * step_s;
        s = c * step_s + s * step_c;
        c = next;
    }
}

// Second order: factors[j] = scale · gauss[j] e^{−i2π (f d_j + ½ q d_j²)}, d_j = s_j − m. The phase's
// second difference along the samples is the constant q h² (h the step), so the phasor advances
// by a ratio that itself advances by e^{−i2π q h²}: two complex multiplications per sample, as
// phase_factors, instead of a cosine and a sine.
void chirped_factors(const SampleAxis& axis, AxisSpan span, const double* gauss, double m, double frequency,
                     double chirp, Complex scale, double* re, double* im) {
    const double h = axis.step_um;
    const double d0 = axis.first_um + span.first * h - m;
    Complex phasor = scale * unit_phasor(frequency * d0 + 0.5 * chirp * d0 * d0);
    Complex ratio = unit_phasor(frequency * h + chirp * h * d0 + 0.5 * chirp * h * h);
    const Complex ratio_step = unit_phasor(chirp * h * h);
    for (int j = 0; j < span.count; ++j) {
        re[j] = gauss[j] * phasor.real();
        im[j] = gauss[j] * phasor.imag();
        phasor = Complex(phasor.real() * ratio.real() - phasor.imag() * ratio.imag(),
                         phasor.real() * ratio.imag() + phasor.imag() * ratio.real());
        ratio = Complex(ratio.real() * ratio_step.real() - ratio.imag() * ratio_step.imag(),
                        ratio.real() * ratio_step.imag() + ratio.imag() * ratio_step.real());
    }
}

// row[j] += phasor · e^{−i2π t j h} · (x_re[j] + i x_im[j]), the step e^{−i2π t h} given: the chirp's
// cross term e^{−i2π B_xy d_x d_y} is, on a grid row (fixed d_y), a plane wave along x of frequency
// t = B_xy d_y, stepped by one multiplication.
void add_row_cross_chirped(Complex* row, Complex phasor, Complex step, const double* x_re, const double* x_im,
                           int count) {
    double* values = reinterpret_cast<double*>(row);
    double c = phasor.real(), s = phasor.imag();
    const double step_c = step.real(), step_s = step.imag();
    for (int j = 0; j < count; ++j) {
        values[2 * j] += c * x_re[j] - s * x_im[j];
        values[2 * j + 1] += c * x_im[j] + s * x_re[j];
        const double next = c * step_c - s * step_s;
        s = c * step_s + s * step_c;
        c = next;
    }
}

// row[j] += factor · (x_re[j] + i x_im[j]) in plain arithmetic (std::complex's product checks for
// infinities in every multiplication).
void add_row(Complex* row, double f_re, double f_im, const double* x_re, const double* x_im, int count) {
    double* values = reinterpret_cast<double*>(row);
    for (int j = 0; j < count; ++j) {
        values[2 * j] += f_re * x_re[j] - f_im * x_im[j];
        values[2 * j + 1] += f_re * x_im[j] + f_im * x_re[j];
    }
}

}  // namespace

ReflectionSource kernel_field_source(const KernelArrays& kernels, const KernelGrid& grid, Point2 centre_um,
                                     double reference_height_um, bool kirchhoff, double chirp_bandwidth) {
    ReflectionSource source;
    source.bandwidth = kSplatSigmas / (2.0 * pi * grid.sigma_um) + chirp_bandwidth;
    const bool chirped = grid.order == 2;
    source.smooth = true;
    auto plan = std::make_shared<SplatPlan>();  // remade when the grid changes (another wavelength)
    source.fill = [&kernels, grid, centre_um, reference_height_um, kirchhoff, chirped, plan](
                      const FootprintSamples& samples, double xi3, double lambda_um, std::vector<std::vector<Complex>>& out) {
        if (!plan->fits(samples)) *plan = plan_splat(kernels, samples, centre_um, grid.sigma_um);
        const int nx = samples.x.count, ny = samples.y.count;
        out.resize(kirchhoff ? 3 : 1);
        for (std::vector<Complex>& component : out) component.assign(static_cast<std::size_t>(nx) * ny, Complex{});
        const double xi3_over_lambda = xi3 / lambda_um;
        const double height_offset = reference_height_um - samples.mean_height_um;
        const double normalisation = 1.0 / (2.0 * pi * grid.sigma_um * grid.sigma_um);  // G_2D
        // Each kernel's factors along x and y at this ξ3, once (a kernel reaches up to two bands),
        // laid out as its Gaussian factors; the y factors carry the coefficient C_k w_k G_2D.
        std::vector<double>& re = plan->phased_re;
        std::vector<double>& im = plan->phased_im;
        re.resize(plan->gauss.size());
        im.resize(plan->gauss.size());
        parallel_for(kernels.size(), 1024, [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) {
                // Yan 2018 eq. 14-15, the phase of a_k·m_k folded into the local (s − m_k)·a_k.
                const Complex c = kernels.weight[k] * normalisation *
                                  std::polar(1.0, -2.0 * pi * xi3_over_lambda * (kernels.height[k] + height_offset));
                const std::size_t xo = plan->x_offset[k], yo = plan->y_offset[k];
                if (chirped) {  // the second-order terms ½ ξ3 H''_xx d_x²/λ and ½ ξ3 H''_yy d_y²/λ
                    chirped_factors(samples.x, plan->x_span[k], &plan->gauss[xo], centre_um.x + kernels.px[k],
                                    xi3_over_lambda * kernels.slope_x[k], xi3_over_lambda * kernels.curvature_xx[k],
                                    1.0, &re[xo], &im[xo]);
                    chirped_factors(samples.y, plan->y_span[k], &plan->gauss[yo], centre_um.y + kernels.py[k],
                                    xi3_over_lambda * kernels.slope_y[k], xi3_over_lambda * kernels.curvature_yy[k],
                                    c, &re[yo], &im[yo]);
                    continue;
                }
                phase_factors(samples.x, plan->x_span[k], &plan->gauss[xo], centre_um.x + kernels.px[k],
                              xi3_over_lambda * kernels.slope_x[k], 1.0, &re[xo], &im[xo]);
                phase_factors(samples.y, plan->y_span[k], &plan->gauss[yo], centre_um.y + kernels.py[k],
                              xi3_over_lambda * kernels.slope_y[k], c, &re[yo], &im[yo]);
            }
        });
        parallel_for(plan->by_band.size(), 1, [&](std::size_t begin, std::size_t end) {
            for (std::size_t band = begin; band < end; ++band) {
                const int row_begin = static_cast<int>(band) * kBandRows;
                const int row_end = std::min(ny, row_begin + kBandRows);
                for (const std::size_t k : plan->by_band[band]) {
                    const AxisSpan sx = plan->x_span[k], sy = plan->y_span[k];
                    const double* x_re = &re[plan->x_offset[k]];
                    const double* x_im = &im[plan->x_offset[k]];
                    const int r_begin = std::max(row_begin, sy.first), r_end = std::min(row_end, sy.first + sy.count);
                    // Second order: the cross term's row phasor e^{−i2π B_xy d0 d_y} and step
                    // e^{−i2π B_xy h_x d_y} are plane waves in d_y, advanced from row to row.
                    Complex cross_start, cross_step, start_ratio, step_ratio;
                    if (chirped) {
                        const double b_xy = xi3_over_lambda * kernels.curvature_xy[k];
                        const double d0 = samples.x.first_um + sx.first * samples.x.step_um - (centre_um.x + kernels.px[k]);
                        const double dy = samples.y.first_um + r_begin * samples.y.step_um - (centre_um.y + kernels.py[k]);
                        cross_start = unit_phasor(b_xy * d0 * dy);
                        cross_step = unit_phasor(b_xy * samples.x.step_um * dy);
                        start_ratio = unit_phasor(b_xy * d0 * samples.y.step_um);
                        step_ratio = unit_phasor(b_xy * samples.x.step_um * samples.y.step_um);
                    }
                    for (int r = r_begin; r < r_end; ++r) {
                        const double f_re = re[plan->y_offset[k] + (r - sy.first)];
                        const double f_im = im[plan->y_offset[k] + (r - sy.first)];
                        const std::size_t at = static_cast<std::size_t>(r) * nx + sx.first;
                        if (chirped) {  // the cross term ξ3 H''_xy d_x d_y/λ
                            const Complex f = Complex(f_re, f_im) * cross_start;
                            add_row_cross_chirped(&out[0][at], f, cross_step, x_re, x_im, sx.count);
                            if (kirchhoff) {
                                add_row_cross_chirped(&out[1][at], f * kernels.slope_x[k], cross_step, x_re, x_im, sx.count);
                                add_row_cross_chirped(&out[2][at], f * kernels.slope_y[k], cross_step, x_re, x_im, sx.count);
                            }
                            cross_start *= start_ratio;
                            cross_step *= step_ratio;
                            continue;
                        }
                        add_row(&out[0][at], f_re, f_im, x_re, x_im, sx.count);
                        if (!kirchhoff) continue;
                        add_row(&out[1][at], f_re * kernels.slope_x[k], f_im * kernels.slope_x[k], x_re, x_im, sx.count);
                        add_row(&out[2][at], f_re * kernels.slope_y[k], f_im * kernels.slope_y[k], x_re, x_im, sx.count);
                    }
                }
            }
        });
    };
    return source;
}

}  // namespace glintscope::gabor
