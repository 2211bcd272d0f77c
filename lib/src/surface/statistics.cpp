#include "glintscope/surface/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "numerics/fftw_plans.hpp"
#include "surface/valid_heights.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

constexpr std::size_t kRowsPerChunk = 32;
constexpr std::size_t kColumnsPerChunk = 128;
constexpr int kTileRows = 16;
constexpr double kNotANumber = std::numeric_limits<double>::quiet_NaN();

struct DeviationSums {
    double squares = 0.0;
    double absolutes = 0.0;
    double slope_x_squares = 0.0;
    std::size_t slope_x_count = 0;
    double slope_y_squares = 0.0;
    std::size_t slope_y_count = 0;
};

// Σ over lines of |FFT(line)|² for the mean-removed, zero-filled heights z and for the validity
// mask m: their inverse transforms are the summed periodic autocorrelations of z and m.
struct PowerSums {
    std::vector<double> heights;
    std::vector<double> mask;
};

// Height deviations and central-difference slopes (periodic; a slope counts only where both
// neighbours are valid).
DeviationSums deviations(const Heightfield& field, double mean) {
    const int rows = field.rows;
    const int cols = field.cols;
    const double inverse_span_x = 1.0 / (2.0 * field.dx_um());
    const double inverse_span_y = 1.0 / (2.0 * field.dy_um());
    const std::size_t chunks = (rows + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<DeviationSums> partial(chunks);
    parallel_for(rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        DeviationSums sums;  // a local, so the loop keeps it in registers
        for (int r = static_cast<int>(begin); r < static_cast<int>(end); ++r) {
            const int up = (r + rows - 1) % rows;
            const int down = (r + 1) % rows;
            for (int c = 0; c < cols; ++c) {
                const double h = field.at(r, c);
                if (!std::isnan(h)) {
                    sums.squares += (h - mean) * (h - mean);
                    sums.absolutes += std::fabs(h - mean);
                }
                const double left = field.at(r, c > 0 ? c - 1 : cols - 1);
                const double right = field.at(r, c + 1 < cols ? c + 1 : 0);
                if (!std::isnan(left) && !std::isnan(right)) {
                    const double slope = (right - left) * inverse_span_x;
                    sums.slope_x_squares += slope * slope;
                    ++sums.slope_x_count;
                }
                // Row r − 1 lies at larger y; the sign does not matter for the rms.
                const double above = field.at(up, c);
                const double below = field.at(down, c);
                if (!std::isnan(above) && !std::isnan(below)) {
                    const double slope = (above - below) * inverse_span_y;
                    sums.slope_y_squares += slope * slope;
                    ++sums.slope_y_count;
                }
            }
        }
        partial[begin / kRowsPerChunk] = sums;
    });
    DeviationSums total;
    for (const DeviationSums& sums : partial) {
        total.squares += sums.squares;
        total.absolutes += sums.absolutes;
        total.slope_x_squares += sums.slope_x_squares;
        total.slope_x_count += sums.slope_x_count;
        total.slope_y_squares += sums.slope_y_squares;
        total.slope_y_count += sums.slope_y_count;
    }
    return total;
}

// Sums |FFT|² over `line_count` lines of length `length`, each line transformed in single
// precision (its power carries ~7 digits, beyond what a 1/e length needs) and summed in double.
// fill(begin, end, z, m, pitch) writes the
// mean-removed, zero-filled heights and (when m is not null) the mask of lines begin..end−1 into z
// and m, line i at offset (i − begin)·pitch. Lines are processed in fixed chunks with one shared plan; partial sums
// are combined in chunk order, so the result does not depend on the thread count.
template <typename Fill>
PowerSums line_power_sums(std::size_t line_count, int length, std::size_t lines_per_chunk, bool with_mask,
                          const Fill& fill) {
    const std::size_t bins = static_cast<std::size_t>(length) / 2 + 1;
    // Lines start at multiples of 32 bytes, the alignment of the planning arrays; the extra 64 bytes
    // keep lines of power-of-two length from mapping onto the same cache sets while gathering.
    const std::size_t pitch = ((static_cast<std::size_t>(length) + 7) & ~std::size_t{7}) + 16;
    auto plan_input = make_fftw_buffer<float>(pitch);
    auto plan_output = make_fftw_buffer<fftwf_complex>(bins);
    const FftwfPlan plan([&] {
        return fftwf_plan_dft_r2c_1d(length, plan_input.get(), plan_output.get(), FFTW_ESTIMATE);
    });
    const std::size_t chunks = (line_count + lines_per_chunk - 1) / lines_per_chunk;
    std::vector<PowerSums> partial(chunks);
    parallel_for(line_count, lines_per_chunk, [&](std::size_t begin, std::size_t end) {
        PowerSums& sums = partial[begin / lines_per_chunk];
        sums.heights.assign(bins, 0.0);
        if (with_mask) sums.mask.assign(bins, 0.0);
        float* z = thread_scratch<float>(0, (end - begin) * pitch);
        float* m = with_mask ? thread_scratch<float>(1, (end - begin) * pitch) : nullptr;
        fftwf_complex* spectrum = thread_scratch<fftwf_complex>(2, bins);
        fill(begin, end, z, m, pitch);
        const auto accumulate = [&](float* line, std::vector<double>& into) {
            fftwf_execute_dft_r2c(plan.get(), line, spectrum);
            for (std::size_t k = 0; k < bins; ++k)
                into[k] += double(spectrum[k][0]) * spectrum[k][0] + double(spectrum[k][1]) * spectrum[k][1];
        };
        for (std::size_t line = 0; line < end - begin; ++line) {
            accumulate(z + line * pitch, sums.heights);
            if (with_mask) accumulate(m + line * pitch, sums.mask);
        }
    });
    PowerSums total{std::vector<double>(bins, 0.0), std::vector<double>(with_mask ? bins : 0, 0.0)};
    for (const PowerSums& sums : partial) {
        for (std::size_t k = 0; k < bins; ++k) total.heights[k] += sums.heights[k];
        for (std::size_t k = 0; k < sums.mask.size(); ++k) total.mask[k] += sums.mask[k];
    }
    return total;
}

void store_deviation(float h, double mean, float* z, float* m, std::size_t at) {
    const bool valid = !std::isnan(h);
    z[at] = valid ? static_cast<float>(h - mean) : 0.0f;
    if (m) m[at] = valid ? 1.0f : 0.0f;
}

// The inverse of a summed power spectrum: the summed periodic autocorrelation at lags 0..length−1.
// (FFTW's transforms are unnormalised; the 1/length makes a mask's autocorrelation a pair count.)
std::vector<double> autocorrelation(const std::vector<double>& power, int length) {
    const std::size_t bins = power.size();
    auto spectrum = make_fftw_buffer<fftw_complex>(bins);
    auto lags = make_fftw_buffer<double>(length);
    const FftwPlan plan([&] { return fftw_plan_dft_c2r_1d(length, spectrum.get(), lags.get(), FFTW_ESTIMATE); });
    for (std::size_t k = 0; k < bins; ++k) {
        spectrum[k][0] = power[k];
        spectrum[k][1] = 0.0;
    }
    fftw_execute(plan.get());
    std::vector<double> result(lags.get(), lags.get() + length);
    for (double& value : result) value /= length;
    return result;
}

// The lag (µm) at which the normalised autocorrelation first falls to `threshold`, linearly
// interpolated between lags. With missing points the masked estimator divides the
// autocorrelation of the zero-filled data by that of the mask (the number of valid pairs at each
// lag), so drop-outs do not pull the estimate towards zero. NaN when the autocorrelation stays
// above the threshold up to half the period, or the heights do not vary.
struct CorrelationLength {
    double length_um = kNotANumber;
    double autocorrelation_at_half = kNotANumber;  // the last lag evaluated
};

CorrelationLength correlation_length(const PowerSums& sums, int length, double pairs_per_lag, double texel_um,
                                     double threshold) {
    const std::vector<double> heights = autocorrelation(sums.heights, length);
    const std::vector<double> pairs =
        sums.mask.empty() ? std::vector<double>(length, pairs_per_lag) : autocorrelation(sums.mask, length);
    const auto covariance = [&](int lag) {
        return pairs[lag] > 0.5 ? heights[lag] / pairs[lag] : kNotANumber;
    };
    const double variance = covariance(0);
    CorrelationLength result;
    if (!(variance > 0.0)) return result;
    double previous = 1.0;
    int previous_lag = 0;
    for (int lag = 1; lag <= length / 2; ++lag) {
        const double rho = covariance(lag) / variance;
        if (std::isnan(rho)) continue;
        if (rho <= threshold) {
            const double fraction = (previous - threshold) / (previous - rho);
            result.length_um = (previous_lag + fraction * (lag - previous_lag)) * texel_um;
            return result;
        }
        previous = rho;
        previous_lag = lag;
    }
    result.autocorrelation_at_half = previous;
    return result;
}

}  // namespace

SurfaceStatistics compute_statistics(const Heightfield& field) {
    const ValidHeights heights = validated_heights(field, "statistics", /*allow_missing=*/true);
    const double valid = static_cast<double>(heights.count);
    SurfaceStatistics stats;
    stats.mean_um = heights.mean;
    stats.min_um = heights.lowest;
    stats.max_um = heights.highest;
    stats.missing_count = field.size() - heights.count;
    stats.missing_fraction = static_cast<double>(stats.missing_count) / static_cast<double>(field.size());

    const DeviationSums deviation = deviations(field, stats.mean_um);
    stats.sq_um = std::sqrt(deviation.squares / valid);
    stats.sa_um = deviation.absolutes / valid;
    stats.rms_slope_x = deviation.slope_x_count > 0
                            ? std::sqrt(deviation.slope_x_squares / static_cast<double>(deviation.slope_x_count))
                            : kNotANumber;
    stats.rms_slope_y = deviation.slope_y_count > 0
                            ? std::sqrt(deviation.slope_y_squares / static_cast<double>(deviation.slope_y_count))
                            : kNotANumber;

    // ACF along x only needs row-wise 1-D spectra (summed over rows), along y column-wise ones:
    // much cheaper than a 2-D transform, and exact for lags on the axes.
    const bool with_mask = stats.missing_count > 0;
    const int rows = field.rows;
    const int cols = field.cols;
    const PowerSums along_x = line_power_sums(
        rows, cols, kRowsPerChunk, with_mask,
        [&](std::size_t begin, std::size_t end, float* z, float* m, std::size_t pitch) {
            for (std::size_t r = begin; r < end; ++r)
                for (int c = 0; c < cols; ++c) {
                    const std::size_t at = (r - begin) * pitch + c;
                    store_deviation(field.at(static_cast<int>(r), c), stats.mean_um, z, m, at);
                }
        });
    // Columns are gathered a block at a time, in tiles of kTileRows rows that stay in cache, so
    // each row segment is read once and each column buffer is written in runs.
    const PowerSums along_y = line_power_sums(
        cols, rows, kColumnsPerChunk, with_mask,
        [&](std::size_t begin, std::size_t end, float* z, float* m, std::size_t pitch) {
            for (int r0 = 0; r0 < rows; r0 += kTileRows)
                for (std::size_t c = begin; c < end; ++c)
                    for (int r = r0; r < std::min(rows, r0 + kTileRows); ++r)
                        store_deviation(field.at(r, static_cast<int>(c)), stats.mean_um, z, m, (c - begin) * pitch + r);
        });
    stats.correlation_threshold = kCorrelationThreshold;
    const CorrelationLength x = correlation_length(along_x, cols, static_cast<double>(rows) * cols, field.texel_um,
                                                   kCorrelationThreshold);
    const CorrelationLength y = correlation_length(along_y, rows, static_cast<double>(rows) * cols, field.dy_um(),
                                                   kCorrelationThreshold);
    stats.correlation_length_x_um = x.length_um;
    stats.correlation_length_y_um = y.length_um;
    stats.autocorrelation_at_half_x = x.autocorrelation_at_half;
    stats.autocorrelation_at_half_y = y.autocorrelation_at_half;
    return stats;
}

}  // namespace glintscope
