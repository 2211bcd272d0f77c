#pragma once
// Internal to surface/: what the areal parameters (areal_parameters.cpp), the spectra
// (spectra.cpp) and the slope distribution (slope_distribution.cpp) share, so that info's Sal and
// the plotted autocorrelation come from the same estimator and Sdq and the slope histogram from
// the same differences.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "numerics/fftw_plans.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/surface/areal_parameters.hpp"
#include "glintscope/surface/heightfield.hpp"
#include "surface/valid_heights.hpp"

namespace glintscope::field_transforms {

constexpr std::size_t kRowsPerChunk = 32;
constexpr std::size_t kColumnsPerBlock = 16;

// The neighbour of index i at offset ±1 along an axis of n samples: wraps on periodic fields,
// -1 outside a non-periodic one.
inline int neighbour(int i, int offset, int n, bool periodic) {
    const int j = i + offset;
    if (j >= 0 && j < n) return j;
    return periodic ? (j + n) % n : -1;
}

// validated_heights(field, what, allow_missing = true), and at least 2 valid heights.
ValidHeights valid_heights(const Heightfield& field, const std::string& what);

// ---- 2-D transforms as batches of 1-D ones (fixed chunks: thread-count independent) ----

// A padded_rows × padded_cols real array held as its half spectrum: row r's r2c transform at
// data + r·stride (stride a multiple of 4 complex values, so every row keeps the planning
// array's 32-byte alignment).
struct HalfSpectrum {
    int rows = 0;
    int cols = 0;
    std::size_t stride = 0;
    FftwBuffer<fftwf_complex> data;

    std::size_t bins() const { return static_cast<std::size_t>(cols) / 2 + 1; }
    float* real_row(int r) { return reinterpret_cast<float*>(data.get() + static_cast<std::size_t>(r) * stride); }
    const float* real_row(int r) const {
        return reinterpret_cast<const float*>(data.get() + static_cast<std::size_t>(r) * stride);
    }
};

// Rows 0..filled_rows−1 from fill_row(r, out) (out has padded_cols floats, pre-zeroed), the rest
// zero; each row transformed in place (r2c), then each column transformed (c2c forward) and
// handed to column_op(k, column, rows, block_index), which may change it. The columns are stored
// back on the rows `stored_rows` lists (sorted), the only rows of the result that hold anything:
// none when column_op only reads. The zero rows are neither transformed nor read.
template <typename FillRow, typename ColumnOp>
HalfSpectrum forward_2d(int padded_rows, int padded_cols, int filled_rows, const FillRow& fill_row,
                        const ColumnOp& column_op, const std::vector<int>& stored_rows = {}) {
    HalfSpectrum spectrum;
    spectrum.rows = padded_rows;
    spectrum.cols = padded_cols;
    spectrum.stride = (spectrum.bins() + 3) & ~std::size_t{3};
    spectrum.data = make_fftw_buffer<fftwf_complex>(spectrum.stride * static_cast<std::size_t>(padded_rows));
    auto plan_row = make_fftw_buffer<fftwf_complex>(spectrum.stride);
    const FftwfPlan row_plan([&] {
        return fftwf_plan_dft_r2c_1d(padded_cols, reinterpret_cast<float*>(plan_row.get()), plan_row.get(),
                                     FFTW_ESTIMATE);
    });
    parallel_for(filled_rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            float* row = spectrum.real_row(static_cast<int>(r));
            std::fill(row, row + 2 * spectrum.stride, 0.0f);
            fill_row(static_cast<int>(r), row);
            fftwf_execute_dft_r2c(row_plan.get(), row, reinterpret_cast<fftwf_complex*>(row));
        }
    });
    auto plan_column = make_fftw_buffer<fftwf_complex>(static_cast<std::size_t>(padded_rows));
    const FftwfPlan column_plan([&] {
        return fftwf_plan_dft_1d(padded_rows, plan_column.get(), plan_column.get(), FFTW_FORWARD, FFTW_ESTIMATE);
    });
    const std::size_t bins = spectrum.bins();
    parallel_for(bins, kColumnsPerBlock, [&](std::size_t begin, std::size_t end) {
        const std::size_t count = end - begin;
        fftwf_complex* block = thread_scratch<fftwf_complex>(0, count * padded_rows);
        for (int r = 0; r < filled_rows; ++r)
            for (std::size_t k = begin; k < end; ++k) {
                const fftwf_complex& value = spectrum.data[r * spectrum.stride + k];
                block[(k - begin) * padded_rows + r][0] = value[0];
                block[(k - begin) * padded_rows + r][1] = value[1];
            }
        for (std::size_t k = 0; k < count; ++k)
            std::fill(reinterpret_cast<float*>(block + k * padded_rows + filled_rows),
                      reinterpret_cast<float*>(block + (k + 1) * padded_rows), 0.0f);
        for (std::size_t k = begin; k < end; ++k) {
            fftwf_complex* column = block + (k - begin) * padded_rows;
            fftwf_execute_dft(column_plan.get(), column, column);
            column_op(k, column, padded_rows, begin / kColumnsPerBlock);
        }
        for (const int r : stored_rows)
            for (std::size_t k = begin; k < end; ++k) {
                fftwf_complex& value = spectrum.data[r * spectrum.stride + k];
                value[0] = block[(k - begin) * padded_rows + r][0];
                value[1] = block[(k - begin) * padded_rows + r][1];
            }
    });
    return spectrum;
}

// The circular autocorrelation (unnormalised) of the array fill_row describes, for the row lags
// 0..max_row_lag: |FFT|² transformed back, row lag r read through real_row(r). The negative row
// lags follow from f(−t) = f(t) (a real array's autocorrelation is even), so only these rows are
// stored and transformed back.
template <typename FillRow>
HalfSpectrum autocorrelation_2d(int padded_rows, int padded_cols, int filled_rows, int max_row_lag,
                                const FillRow& fill_row) {
    auto plan_column = make_fftw_buffer<fftwf_complex>(static_cast<std::size_t>(padded_rows));
    const FftwfPlan inverse_column_plan([&] {
        return fftwf_plan_dft_1d(padded_rows, plan_column.get(), plan_column.get(), FFTW_BACKWARD, FFTW_ESTIMATE);
    });
    std::vector<int> needed(static_cast<std::size_t>(std::min(max_row_lag, padded_rows - 1)) + 1);
    for (std::size_t lag = 0; lag < needed.size(); ++lag) needed[lag] = static_cast<int>(lag);
    HalfSpectrum spectrum = forward_2d(
        padded_rows, padded_cols, filled_rows, fill_row,
        [&](std::size_t, fftwf_complex* column, int rows, std::size_t) {
            for (int r = 0; r < rows; ++r) {
                column[r][0] = column[r][0] * column[r][0] + column[r][1] * column[r][1];
                column[r][1] = 0.0f;
            }
            fftwf_execute_dft(inverse_column_plan.get(), column, column);
        },
        needed);
    auto plan_row = make_fftw_buffer<fftwf_complex>(spectrum.stride);
    const FftwfPlan inverse_row_plan([&] {
        return fftwf_plan_dft_c2r_1d(padded_cols, plan_row.get(), reinterpret_cast<float*>(plan_row.get()),
                                     FFTW_ESTIMATE);
    });
    parallel_for(needed.size(), kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            fftwf_complex* row = spectrum.data.get() + static_cast<std::size_t>(needed[i]) * spectrum.stride;
            fftwf_execute_dft_c2r(inverse_row_plan.get(), row, reinterpret_cast<float*>(row));
        }
    });
    return spectrum;
}

// The normalised autocorrelation f(t) = Σ z(s) z(s+t) / Σ z² of the mean-removed heights, each sum
// over the pairs inside the field divided by their number (missing points and the border do not
// bias it; circular on periodic fields), for lags up to half the field along each axis.
class Autocorrelation {
public:
    Autocorrelation(const Heightfield& field, const ValidHeights& heights);

    int max_row_lag() const { return max_row_lag_; }
    int max_col_lag() const { return max_col_lag_; }

    // f at the integer lag (row_lag, col_lag) in samples; NaN where no pair of valid points has it.
    double at(int row_lag, int col_lag) const { return covariance(row_lag, col_lag) / variance_; }

    // f at a fractional lag, bilinear between the four integer lags around it.
    double interpolate(double row_lag, double col_lag) const;

private:
    double covariance(int row_lag, int col_lag) const;

    const Heightfield& field_;
    int rows_ = 0, cols_ = 0, padded_rows_ = 0, padded_cols_ = 0, max_row_lag_ = 0, max_col_lag_ = 0;
    HalfSpectrum heights_;
    HalfSpectrum pairs_;
    double variance_ = 1.0;
};

// From the autocorrelation: Sal, the slowest decay, Str and their bounds, and the lags evaluated
// (areal_parameters.hpp), for the threshold p.threshold; the other fields of p are left alone.
void decay_parameters(const Autocorrelation& acf, double dx, double dy, ArealParameters& p);

// Throws Error unless s lies in (0, 1).
void check_threshold(double threshold);

}  // namespace glintscope::field_transforms
