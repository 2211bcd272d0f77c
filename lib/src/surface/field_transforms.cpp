#include "surface/field_transforms.hpp"

#include <limits>

#include "numerics/chirp_z.hpp"
#include "glintscope/core/error.hpp"

namespace glintscope::field_transforms {
ValidHeights valid_heights(const Heightfield& field, const std::string& what) {
    const ValidHeights valid = validated_heights(field, what, /*allow_missing=*/true);
    if (valid.count < 2) throw Error(what + " need at least 2 valid heights");
    return valid;
}

Autocorrelation::Autocorrelation(const Heightfield& field, const ValidHeights& valid) : field_(field) {
    rows_ = field.rows;
    cols_ = field.cols;
    max_row_lag_ = rows_ / 2;
    max_col_lag_ = cols_ / 2;
    // Zero padding by half the field makes the circular sums the sums over pairs inside the field
    // for every evaluated lag (a lag t also collects the pairs at t − padded, none once padded ≥
    // n + t); a periodic field is its own continuation. 8192 pads to 12288 = 3·2¹², not 12348.
    padded_rows_ = field.periodic ? rows_ : smooth_fft_size(rows_ + max_row_lag_);
    padded_cols_ = field.periodic ? cols_ : smooth_fft_size(cols_ + max_col_lag_);
    const double mean = valid.mean;
    heights_ = autocorrelation_2d(padded_rows_, padded_cols_, rows_, max_row_lag_, [&](int r, float* out) {
        for (int c = 0; c < cols_; ++c) {
            const float h = field.at(r, c);
            out[c] = std::isnan(h) ? 0.0f : static_cast<float>(h - mean);
        }
    });
    if (valid.missing)
        pairs_ = autocorrelation_2d(padded_rows_, padded_cols_, rows_, max_row_lag_, [&](int r, float* out) {
            for (int c = 0; c < cols_; ++c) out[c] = std::isnan(field.at(r, c)) ? 0.0f : 1.0f;
        });
    variance_ = covariance(0, 0);
}

double Autocorrelation::interpolate(double row_lag, double col_lag) const {
    const double r0 = std::floor(row_lag);
    const double c0 = std::floor(col_lag);
    const double fr = row_lag - r0;
    const double fc = col_lag - c0;
    const int r = static_cast<int>(r0);
    const int c = static_cast<int>(c0);
    return (1 - fr) * ((1 - fc) * at(r, c) + fc * at(r, c + 1)) + fr * ((1 - fc) * at(r + 1, c) + fc * at(r + 1, c + 1));
}

double Autocorrelation::covariance(int row_lag, int col_lag) const {
    row_lag = std::clamp(row_lag, -max_row_lag_, max_row_lag_);
    col_lag = std::clamp(col_lag, -max_col_lag_, max_col_lag_);
    if (row_lag < 0) {  // only the rows of lags ≥ 0 are held: f(−t) = f(t)
        row_lag = -row_lag;
        col_lag = -col_lag;
    }
    const int r = (row_lag + padded_rows_) % padded_rows_;
    const int c = (col_lag + padded_cols_) % padded_cols_;
    const double sum = heights_.real_row(r)[c];
    double pairs = 0.0;
    if (pairs_.data) {
        pairs = pairs_.real_row(r)[c];
        // The transforms carry a factor padded_rows·padded_cols on both sums.
        if (pairs < 0.5 * padded_rows_ * double(padded_cols_)) return std::numeric_limits<double>::quiet_NaN();
    } else {
        pairs = field_.periodic ? double(rows_) * cols_ : double(rows_ - std::abs(row_lag)) * (cols_ - std::abs(col_lag));
        pairs *= double(padded_rows_) * padded_cols_;
    }
    return sum / pairs;
}

}  // namespace glintscope::field_transforms
