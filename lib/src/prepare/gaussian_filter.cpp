// ISO 16610-61's areal Gaussian filter: the mean surface is the heights convolved with
// s(x, y) = 1/(αλ)² exp(−π (x² + y²)/(αλ)²), α = √(ln 2 / π), whose transmission
// exp(−π (αλ/Λ)²) is 50% at the nesting index λ (ISO 16610-61 eq. 1). The kernel is separable,
// so it runs as 1-D convolutions along rows, then columns, each through FFTs of the line.
// On a non-periodic field each line is zero-padded and the convolution of the heights is
// divided by that of the validity mask (a normalised convolution), so the border and missing
// points do not pull the mean surface towards zero; on a periodic field the kernel wraps.
#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "glintscope/prepare/prepare.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"
#include "numerics/chirp_z.hpp"
#include "numerics/fftw_plans.hpp"

namespace glintscope {
namespace {

constexpr std::size_t kLinesPerChunk = 16;
const double kAlpha = std::sqrt(std::log(2.0) / pi);
// exp(−π (x/αλ)²) < 1e-12 beyond 3αλ: the kernel is cut there.
constexpr double kKernelHalfWidths = 3.0;

// The FFT of the sampled 1-D kernel on a line of `length` samples (wrapped), normalised to unit
// sum so that a constant passes unchanged.
std::vector<std::complex<double>> kernel_spectrum(int length, double spacing_um, double nesting_um) {
    const double width = kAlpha * nesting_um;
    const int half = static_cast<int>(std::ceil(kKernelHalfWidths * width / spacing_um));
    auto kernel = make_fftw_buffer<double>(length);
    std::fill(kernel.get(), kernel.get() + length, 0.0);
    double sum = 0.0;
    for (int k = -half; k <= half; ++k) {
        const double weight = std::exp(-pi * std::pow(k * spacing_um / width, 2));  // ISO 16610-61 eq. 1
        kernel[((k % length) + length) % length] += weight;
        sum += weight;
    }
    const int bins = length / 2 + 1;
    auto spectrum = make_fftw_buffer<fftw_complex>(bins);
    const FftwPlan plan([&] { return fftw_plan_dft_r2c_1d(length, kernel.get(), spectrum.get(), FFTW_ESTIMATE); });
    fftw_execute(plan.get());
    std::vector<std::complex<double>> result(bins);
    for (int k = 0; k < bins; ++k) result[k] = {spectrum[k][0] / (sum * length), spectrum[k][1] / (sum * length)};
    return result;
}

// Convolves `count` lines of `size` samples (line i's sample j at values[i·line_step + j·step])
// with the kernel, in place; `weights` (same layout, or null) gets the same convolution.
void convolve_lines(std::vector<double>& values, std::vector<double>* weights, std::size_t count, int size,
                    std::size_t line_step, std::size_t step, bool periodic, double spacing_um, double nesting_um) {
    const double width = kAlpha * nesting_um;
    const int half = static_cast<int>(std::ceil(kKernelHalfWidths * width / spacing_um));
    const int length = periodic ? size : smooth_fft_size(size + half + 1);
    const std::vector<std::complex<double>> kernel = kernel_spectrum(length, spacing_um, nesting_um);
    const int bins = length / 2 + 1;
    auto plan_line = make_fftw_buffer<double>(length);
    auto plan_spectrum = make_fftw_buffer<fftw_complex>(bins);
    const FftwPlan forward(
        [&] { return fftw_plan_dft_r2c_1d(length, plan_line.get(), plan_spectrum.get(), FFTW_ESTIMATE); });
    const FftwPlan inverse(
        [&] { return fftw_plan_dft_c2r_1d(length, plan_spectrum.get(), plan_line.get(), FFTW_ESTIMATE); });
    parallel_for(count, kLinesPerChunk, [&](std::size_t begin, std::size_t end) {
        double* line = thread_scratch<double>(0, length);
        fftw_complex* spectrum = thread_scratch<fftw_complex>(1, bins);
        const auto filter = [&](std::vector<double>& data, std::size_t i) {
            std::fill(line, line + length, 0.0);
            for (int j = 0; j < size; ++j) line[j] = data[i * line_step + j * step];
            fftw_execute_dft_r2c(forward.get(), line, spectrum);
            for (int k = 0; k < bins; ++k) {
                const std::complex<double> value = std::complex<double>(spectrum[k][0], spectrum[k][1]) * kernel[k];
                spectrum[k][0] = value.real();
                spectrum[k][1] = value.imag();
            }
            fftw_execute_dft_c2r(inverse.get(), spectrum, line);
            for (int j = 0; j < size; ++j) data[i * line_step + j * step] = line[j];
        };
        for (std::size_t i = begin; i < end; ++i) {
            filter(values, i);
            if (weights) filter(*weights, i);
        }
    });
}

// The mean surface: the Gaussian-weighted average of the valid heights around each point.
std::vector<double> mean_surface(const Heightfield& field, double nesting_um) {
    const int rows = field.rows, cols = field.cols;
    std::vector<double> values(field.size()), weights;
    const bool normalise = !field.periodic || count_missing(field) > 0;
    if (normalise) weights.resize(field.size());
    for (std::size_t i = 0; i < field.size(); ++i) {
        const bool valid = !std::isnan(field.heights_um[i]);
        values[i] = valid ? field.heights_um[i] : 0.0;
        if (normalise) weights[i] = valid ? 1.0 : 0.0;
    }
    std::vector<double>* mask = normalise ? &weights : nullptr;
    convolve_lines(values, mask, rows, cols, cols, 1, field.periodic, field.dx_um(), nesting_um);
    convolve_lines(values, mask, cols, rows, 1, cols, field.periodic, field.dy_um(), nesting_um);
    if (normalise)
        for (std::size_t i = 0; i < values.size(); ++i) values[i] /= weights[i];
    return values;
}

void check_nesting_index(const Heightfield& field, double nesting_um, const char* name) {
    if (!(nesting_um > 0.0) || !std::isfinite(nesting_um))
        throw Error(std::string(name) + " nesting index must be a positive length, got " + shortest_text(nesting_um));
    // A kernel many times the field would only average the whole field; the line FFTs grow with it.
    const double longest = 20.0 * std::max(field.width_um(), field.height_um());
    if (nesting_um > longest)
        throw Error(std::string(name) + " nesting index " + format_length(nesting_um) + " is more than 20 times the field (" +
                    format_length(field.width_um()) + " x " + format_length(field.height_um()) + ")");
}

}  // namespace

void apply_s_filter(Heightfield& field, double nesting_um) {
    check_nesting_index(field, nesting_um, "S-filter");
    const std::vector<double> smooth = mean_surface(field, nesting_um);
    for (std::size_t i = 0; i < field.size(); ++i)
        if (!std::isnan(field.heights_um[i])) field.heights_um[i] = static_cast<float>(smooth[i]);
    record_preparation(field, "S-filter: ISO 16610-61 Gaussian, nesting index " + format_length(nesting_um));
}

void apply_l_filter(Heightfield& field, double nesting_um) {
    check_nesting_index(field, nesting_um, "L-filter");
    const std::vector<double> smooth = mean_surface(field, nesting_um);
    for (std::size_t i = 0; i < field.size(); ++i)
        if (!std::isnan(field.heights_um[i]))
            field.heights_um[i] = static_cast<float>(field.heights_um[i] - smooth[i]);
    record_preparation(field, "L-filter: ISO 16610-61 Gaussian, nesting index " + format_length(nesting_um));
}

}  // namespace glintscope
