// Gaussian random fields by spectral synthesis: white noise in the Fourier domain, filtered by the
// square root of the power spectral density of the requested correlation function (Stam 1999
// §4.1), transformed back to heights.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "generate/correlation_spectrum.hpp"
#include "core/counter_rng.hpp"
#include "numerics/fftw_plans.hpp"
#include "generators.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

constexpr std::size_t kRowsPerChunk = 16;
constexpr std::size_t kColumnsPerChunk = 8;

// Filtered complex white noise on the half spectrum (rows × (cols/2 + 1)) that FFTW's c2r expects.
// Bins on the columns kx = 0 and kx = Nyquist are their own mirror images up to ky → −ky; there
// the noise is made Hermitian (Z(−k) = Z(k)*) so the synthesised field is real.
void fill_spectrum(fftwf_complex* spectrum, const GridSpec& grid, const GaussianFieldParameters& parameters,
                   std::uint64_t seed) {
    const int rows = grid.rows;
    const int cols = grid.cols;
    const int bins = cols / 2 + 1;
    const SampledPowerSpectrum psd(parameters, grid);
    const CounterRng rng(seed, kStreamGaussianNoise);
    parallel_for(rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        for (int i = static_cast<int>(begin); i < static_cast<int>(end); ++i) {
            const int mirror_row = (rows - i) % rows;
            for (int j = 0; j < bins; ++j) {
                const bool self_mirrored_column = j == 0 || 2 * j == cols;
                // Mirrored bins take noise and amplitude from the same row, so they are exact conjugates.
                const int noise_row = self_mirrored_column ? std::min(i, mirror_row) : i;
                double re = 0.0;
                double im = 0.0;
                rng.normal_pair(static_cast<std::uint64_t>(noise_row) * bins + j, re, im);
                if (self_mirrored_column && i == mirror_row) {
                    im = 0.0;  // a real bin with unit variance
                } else {
                    re *= std::numbers::sqrt2 / 2.0;  // complex bins with E|Z|² = 1
                    im *= (self_mirrored_column && i > mirror_row ? -1.0 : 1.0) * std::numbers::sqrt2 / 2.0;
                }
                const double amplitude = (i == 0 && j == 0) ? 0.0 : std::sqrt(psd.aliased(noise_row, j));
                fftwf_complex& bin = spectrum[static_cast<std::size_t>(i) * bins + j];
                bin[0] = static_cast<float>(amplitude * re);
                bin[1] = static_cast<float>(amplitude * im);
            }
        }
    });
}

// Inverse transforms along y: each half-spectrum column is gathered into a contiguous buffer.
// Columns start at multiples of 32 bytes so every buffer has the alignment the plan was made for;
// the extra 64 bytes keep power-of-two columns from mapping onto the same cache sets.
void inverse_transform_columns(fftwf_complex* spectrum, int rows, int bins) {
    const std::size_t pitch = ((static_cast<std::size_t>(rows) + 3) & ~std::size_t{3}) + 8;
    auto plan_buffer = make_fftw_buffer<fftwf_complex>(pitch);
    const FftwfPlan plan([&] {
        return fftwf_plan_dft_1d(rows, plan_buffer.get(), plan_buffer.get(), FFTW_BACKWARD, FFTW_ESTIMATE);
    });
    parallel_for(bins, kColumnsPerChunk, [&](std::size_t begin, std::size_t end) {
        const std::size_t width = end - begin;
        fftwf_complex* columns = thread_scratch<fftwf_complex>(0, width * pitch);
        for (int i = 0; i < rows; ++i)
            for (std::size_t j = 0; j < width; ++j) {
                const fftwf_complex& bin = spectrum[static_cast<std::size_t>(i) * bins + begin + j];
                columns[j * pitch + i][0] = bin[0];
                columns[j * pitch + i][1] = bin[1];
            }
        for (std::size_t j = 0; j < width; ++j) {
            fftwf_complex* column = columns + j * pitch;
            fftwf_execute_dft(plan.get(), column, column);
        }
        for (int i = 0; i < rows; ++i)
            for (std::size_t j = 0; j < width; ++j) {
                fftwf_complex& bin = spectrum[static_cast<std::size_t>(i) * bins + begin + j];
                bin[0] = columns[j * pitch + i][0];
                bin[1] = columns[j * pitch + i][1];
            }
    });
}

// Complex-to-real inverse transforms along x, row by row, into the heights.
void inverse_transform_rows(const fftwf_complex* spectrum, int rows, int cols, std::vector<float>& heights) {
    const int bins = cols / 2 + 1;
    auto plan_input = make_fftw_buffer<fftwf_complex>(bins);
    auto plan_output = make_fftw_buffer<float>(cols);
    const FftwfPlan plan([&] {
        return fftwf_plan_dft_c2r_1d(cols, plan_input.get(), plan_output.get(), FFTW_ESTIMATE);
    });
    parallel_for(rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        fftwf_complex* input = thread_scratch<fftwf_complex>(0, bins);
        float* output = thread_scratch<float>(1, cols);
        for (std::size_t i = begin; i < end; ++i) {
            const fftwf_complex* row = spectrum + i * bins;
            for (int j = 0; j < bins; ++j) {
                input[j][0] = row[j][0];
                input[j][1] = row[j][1];
            }
            fftwf_execute_dft_c2r(plan.get(), input, output);
            std::copy(output, output + cols, heights.begin() + static_cast<std::ptrdiff_t>(i * cols));
        }
    });
}

// Removes the (round-off) mean and rescales so that Sq is exactly σ_h: a single tile's Sq would
// otherwise scatter by a few per cent around σ_h when the correlation lengths are long.
void normalise(std::vector<float>& heights, double sigma_h_um) {
    const std::size_t chunk = std::size_t{1} << 16;
    const std::size_t chunks = (heights.size() + chunk - 1) / chunk;
    std::vector<double> sums(chunks);
    std::vector<double> squares(chunks);
    parallel_for(heights.size(), chunk, [&](std::size_t begin, std::size_t end) {
        double sum = 0.0;
        double square = 0.0;
        for (std::size_t i = begin; i < end; ++i) {
            sum += heights[i];
            square += static_cast<double>(heights[i]) * heights[i];
        }
        sums[begin / chunk] = sum;
        squares[begin / chunk] = square;
    });
    double sum = 0.0;
    double square = 0.0;
    for (std::size_t c = 0; c < chunks; ++c) {
        sum += sums[c];
        square += squares[c];
    }
    const double n = static_cast<double>(heights.size());
    const double mean = sum / n;
    const double variance = square / n - mean * mean;
    const double scale = variance > 0.0 ? sigma_h_um / std::sqrt(variance) : 0.0;
    parallel_for(heights.size(), chunk, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) heights[i] = static_cast<float>((heights[i] - mean) * scale);
    });
}

}  // namespace

std::vector<float> gaussian_random_field(const GridSpec& grid, const GaussianFieldParameters& parameters,
                                         std::uint64_t seed) {
    const int bins = grid.cols / 2 + 1;
    // Single precision halves the memory: the spectrum and the heights together take 8 bytes per
    // sample (0.5 GB for 8192²).
    auto spectrum = make_fftw_buffer<fftwf_complex>(static_cast<std::size_t>(grid.rows) * bins);
    fill_spectrum(spectrum.get(), grid, parameters, seed);
    inverse_transform_columns(spectrum.get(), grid.rows, bins);
    std::vector<float> heights(static_cast<std::size_t>(grid.rows) * grid.cols);
    inverse_transform_rows(spectrum.get(), grid.rows, grid.cols, heights);
    spectrum.reset();
    normalise(heights, parameters.sigma_h_um);
    return heights;
}

}  // namespace glintscope
