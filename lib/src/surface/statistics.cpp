#include "glintscope/surface/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "numerics/fftw_plans.hpp"
#include "surface/field_transforms.hpp"
#include "surface/statistics_parts.hpp"
#include "numerics/chirp_z.hpp"
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

// One row's terms, NaN where undefined: the squared and absolute deviations from the mean and the
// squared central-difference slopes along x (wrapping at the row's ends) and y (from the rows
// above and below). Branch-free over the interior columns, so the compiler vectorises it.
struct RowTerms {
    double* squares;
    double* absolutes;
    double* slope_x_squares;
    double* slope_y_squares;
};

void row_terms(const float* row, const float* above, const float* below, int cols, double mean,
               double inverse_span_x, double inverse_span_y, const RowTerms& out) {
    for (int c = 0; c < cols; ++c) {
        const double deviation = double(row[c]) - mean;
        out.squares[c] = deviation * deviation;
        out.absolutes[c] = std::fabs(deviation);
        // Row r − 1 lies at larger y; the sign does not matter for the rms.
        const double slope_y = (double(above[c]) - double(below[c])) * inverse_span_y;
        out.slope_y_squares[c] = slope_y * slope_y;
    }
    for (int c = 1; c + 1 < cols; ++c) {
        const double slope_x = (double(row[c + 1]) - double(row[c - 1])) * inverse_span_x;
        out.slope_x_squares[c] = slope_x * slope_x;
    }
    for (const int c : {0, cols - 1}) {
        const int left = c > 0 ? c - 1 : cols - 1, right = c + 1 < cols ? c + 1 : 0;
        const double slope_x = (double(row[right]) - double(row[left])) * inverse_span_x;
        out.slope_x_squares[c] = slope_x * slope_x;
    }
}

// Height deviations and central-difference slopes (periodic; a slope counts only where both
// neighbours are valid). Each row's terms are summed in column order, after row_terms.
DeviationSums deviations(const Heightfield& field, double mean) {
    const int rows = field.rows;
    const int cols = field.cols;
    const double inverse_span_x = 1.0 / (2.0 * field.dx_um());
    const double inverse_span_y = 1.0 / (2.0 * field.dy_um());
    const std::size_t chunks = (rows + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<DeviationSums> partial(chunks);
    const auto row_at = [&](int r) { return field.heights_um.data() + static_cast<std::size_t>(r) * cols; };
    parallel_for(rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        DeviationSums sums;  // a local, so the loop keeps it in registers
        const RowTerms terms{thread_scratch<double>(0, cols), thread_scratch<double>(1, cols),
                             thread_scratch<double>(2, cols), thread_scratch<double>(3, cols)};
        for (int r = static_cast<int>(begin); r < static_cast<int>(end); ++r) {
            row_terms(row_at(r), row_at((r + rows - 1) % rows), row_at((r + 1) % rows), cols, mean, inverse_span_x,
                      inverse_span_y, terms);
            for (int c = 0; c < cols; ++c) {
                if (!std::isnan(terms.squares[c])) {
                    sums.squares += terms.squares[c];
                    sums.absolutes += terms.absolutes[c];
                }
                if (!std::isnan(terms.slope_x_squares[c])) {
                    sums.slope_x_squares += terms.slope_x_squares[c];
                    ++sums.slope_x_count;
                }
                if (!std::isnan(terms.slope_y_squares[c])) {
                    sums.slope_y_squares += terms.slope_y_squares[c];
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

// Sums |FFT|² over `line_count` lines of length `length`, zero-padded to `transform_length`, each
// line transformed in single precision (its power carries ~7 digits, beyond what a 1/e length
// needs) and summed in double. fill(begin, end, z, m, pitch) writes the mean-removed, zero-filled
// heights and (when m is not null) the mask of lines begin..end−1 into z and m, line i at offset
// (i − begin)·pitch. Lines are processed in fixed chunks with one shared plan; partial sums are
// combined in chunk order, so the result does not depend on the thread count.
template <typename Fill>
PowerSums line_power_sums(std::size_t line_count, int length, int transform_length, std::size_t lines_per_chunk,
                          bool with_mask, const Fill& fill) {
    const std::size_t bins = static_cast<std::size_t>(transform_length) / 2 + 1;
    // Lines start at multiples of 32 bytes, the alignment of the planning arrays; the extra 64 bytes
    // keep lines of power-of-two length from mapping onto the same cache sets while gathering.
    const std::size_t pitch = ((static_cast<std::size_t>(transform_length) + 7) & ~std::size_t{7}) + 16;
    auto plan_input = make_fftw_buffer<float>(pitch);
    auto plan_output = make_fftw_buffer<fftwf_complex>(bins);
    const FftwfPlan plan([&] {
        return fftwf_plan_dft_r2c_1d(transform_length, plan_input.get(), plan_output.get(), FFTW_ESTIMATE);
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
        for (std::size_t line = 0; line < end - begin; ++line) {
            std::fill(z + line * pitch + length, z + line * pitch + transform_length, 0.0f);
            if (with_mask) std::fill(m + line * pitch + length, m + line * pitch + transform_length, 0.0f);
        }
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

// A correlation length, or NaN with the autocorrelation at the last lag evaluated.
struct CorrelationLength {
    double length_um = kNotANumber;
    double autocorrelation_at_half = kNotANumber;  // the last lag evaluated
};

// The lag (µm) at which the normalised autocorrelation rho(lag) (NaN where no pair of valid
// points has the lag) first falls to `threshold` over lags 1..max_lag, linearly interpolated
// between lags; NaN when it stays above the threshold up to max_lag (half the field).
template <typename Rho>
CorrelationLength first_decay(const Rho& rho, int max_lag, double texel_um, double threshold) {
    CorrelationLength result;
    double previous = 1.0;
    int previous_lag = 0;
    for (int lag = 1; lag <= max_lag; ++lag) {
        const double value = rho(lag);
        if (std::isnan(value)) continue;
        if (value <= threshold) {
            const double fraction = (previous - threshold) / (previous - value);
            result.length_um = (previous_lag + fraction * (lag - previous_lag)) * texel_um;
            return result;
        }
        previous = value;
        previous_lag = lag;
    }
    result.autocorrelation_at_half = previous;
    return result;
}

// From the lines' summed spectra (line_power_sums over `lines` lines of `length` samples,
// transformed at `transform_length`). With missing points the masked estimator divides the
// autocorrelation of the zero-filled data by that of the mask (the number of valid pairs at each
// lag), so drop-outs do not pull the estimate towards zero; without, the pairs at lag t number
// lines·length on a periodic field (circular) and lines·(length − t) on a non-periodic one.
CorrelationLength correlation_length(const PowerSums& sums, std::size_t lines, int length, int transform_length,
                                     bool periodic, double texel_um) {
    const std::vector<double> heights = autocorrelation(sums.heights, transform_length);
    const std::vector<double> mask_pairs = sums.mask.empty() ? std::vector<double>{} : autocorrelation(sums.mask, transform_length);
    const auto covariance = [&](int lag) {
        const double pairs = !mask_pairs.empty() ? mask_pairs[lag]
                             : periodic          ? double(lines) * length
                                                 : double(lines) * (length - lag);
        return pairs > 0.5 ? heights[lag] / pairs : kNotANumber;
    };
    const double variance = covariance(0);
    if (!(variance > 0.0)) return {};
    return first_decay([&](int lag) { return covariance(lag) / variance; }, length / 2, texel_um,
                       kCorrelationThreshold);
}

// The transform length for lines of n samples: n on a periodic field; otherwise padded with
// zeros so that no lag up to n/2 wraps around (the autocorrelation then sums the pairs inside the
// field, as the areal parameters' does: field_transforms.cpp).
int line_transform_length(int n, bool periodic) { return periodic ? n : smooth_fft_size(n + n / 2); }

}  // namespace

SurfaceStatistics statistics_without_correlation(const Heightfield& field, const ValidHeights& heights) {
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
    stats.correlation_threshold = kCorrelationThreshold;
    return stats;
}

void line_correlation_lengths(const Heightfield& field, SurfaceStatistics& stats) {
    // ACF along x only needs row-wise 1-D spectra (summed over rows), along y column-wise ones:
    // much cheaper than a 2-D transform, and exact for lags on the axes.
    const bool with_mask = stats.missing_count > 0;
    const int rows = field.rows;
    const int cols = field.cols;
    const int row_transform = line_transform_length(cols, field.periodic);
    const int column_transform = line_transform_length(rows, field.periodic);
    const PowerSums along_x = line_power_sums(
        rows, cols, row_transform, kRowsPerChunk, with_mask,
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
        cols, rows, column_transform, kColumnsPerChunk, with_mask,
        [&](std::size_t begin, std::size_t end, float* z, float* m, std::size_t pitch) {
            for (int r0 = 0; r0 < rows; r0 += kTileRows)
                for (std::size_t c = begin; c < end; ++c)
                    for (int r = r0; r < std::min(rows, r0 + kTileRows); ++r)
                        store_deviation(field.at(r, static_cast<int>(c)), stats.mean_um, z, m, (c - begin) * pitch + r);
        });
    const CorrelationLength x =
        correlation_length(along_x, rows, cols, row_transform, field.periodic, field.dx_um());
    const CorrelationLength y =
        correlation_length(along_y, cols, rows, column_transform, field.periodic, field.dy_um());
    stats.correlation_length_x_um = x.length_um;
    stats.correlation_length_y_um = y.length_um;
    stats.autocorrelation_at_half_x = x.autocorrelation_at_half;
    stats.autocorrelation_at_half_y = y.autocorrelation_at_half;
}

void read_correlation_lengths(const field_transforms::Autocorrelation& acf, double dx, double dy,
                              SurfaceStatistics& stats) {
    const CorrelationLength x = first_decay([&](int lag) { return acf.at(0, lag); }, acf.max_col_lag(), dx,
                                            kCorrelationThreshold);
    const CorrelationLength y = first_decay([&](int lag) { return acf.at(lag, 0); }, acf.max_row_lag(), dy,
                                            kCorrelationThreshold);
    stats.correlation_length_x_um = x.length_um;
    stats.correlation_length_y_um = y.length_um;
    stats.autocorrelation_at_half_x = x.autocorrelation_at_half;
    stats.autocorrelation_at_half_y = y.autocorrelation_at_half;
}

SurfaceStatistics compute_statistics(const Heightfield& field) {
    SurfaceStatistics stats =
        statistics_without_correlation(field, validated_heights(field, "statistics", /*allow_missing=*/true));
    line_correlation_lengths(field, stats);
    return stats;
}

}  // namespace glintscope
