#include "glintscope/surface/spectra.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/parallel.hpp"
#include "surface/field_transforms.hpp"

namespace glintscope {
namespace {

using namespace field_transforms;

// The sums of |F|² over one block of spectrum columns, combined afterwards in block order so that
// the result does not depend on the thread count.
struct BlockPower {
    std::vector<double> y;       // by row index j of the transform
    std::vector<double> radial;  // by annulus
    std::vector<double> cells;   // grid cells per annulus
};

// Hann along an axis of n samples, or 1 everywhere when the field is periodic.
std::vector<float> window_of(int n, bool periodic) {
    std::vector<float> window(n, 1.0f);
    if (!periodic)
        for (int i = 0; i < n; ++i) window[i] = static_cast<float>(std::pow(std::sin(pi * (i + 0.5) / n), 2));
    return window;
}

}  // namespace

PowerSpectralDensity compute_power_spectral_density(const Heightfield& field) {
    const double mean = valid_heights(field, "power spectral density").mean;
    const int rows = field.rows, cols = field.cols;
    const double dx = field.dx_um(), dy = field.dy_um();
    const std::vector<float> window_x = window_of(cols, field.periodic), window_y = window_of(rows, field.periodic);
    double window_power = 0.0, weighted_squares = 0.0;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            const double h = field.at(r, c);
            if (std::isnan(h)) continue;
            const double w = double(window_x[c]) * window_y[r];
            window_power += w * w;
            weighted_squares += w * w * (h - mean) * (h - mean);
        }

    PowerSpectralDensity psd;
    psd.hann_window = !field.periodic;
    psd.frequency_step_x_per_um = 1.0 / (cols * dx);
    psd.frequency_step_y_per_um = 1.0 / (rows * dy);
    psd.mean_square_um2 = weighted_squares / window_power;
    const double step = std::max(psd.frequency_step_x_per_um, psd.frequency_step_y_per_um);
    const int annuli = static_cast<int>(std::hypot(0.5 / dx, 0.5 / dy) / step) + 2;
    const std::size_t bins_x = static_cast<std::size_t>(cols) / 2 + 1;
    const std::size_t blocks = (bins_x + kColumnsPerBlock - 1) / kColumnsPerBlock;
    std::vector<BlockPower> partial(blocks, BlockPower{std::vector<double>(rows, 0.0),
                                                       std::vector<double>(annuli, 0.0),
                                                       std::vector<double>(annuli, 0.0)});
    std::vector<double> x_power(bins_x, 0.0);
    forward_2d(
        rows, cols, rows,
        [&](int r, float* out) {
            for (int c = 0; c < cols; ++c) {
                const float h = field.at(r, c);
                out[c] = std::isnan(h) ? 0.0f : static_cast<float>(h - mean) * window_x[c] * window_y[r];
            }
        },
        [&](std::size_t k, fftwf_complex* column, int n, std::size_t block) {
            // Column k > 0 below Nyquist also stands for its mirror −k (the conjugate at (−k, −j)).
            const bool mirrored = k > 0 && 2 * k != static_cast<std::size_t>(cols);
            BlockPower& sums = partial[block];
            const double fx = k * psd.frequency_step_x_per_um;
            for (int j = 0; j < n; ++j) {
                const double power = double(column[j][0]) * column[j][0] + double(column[j][1]) * column[j][1];
                x_power[k] += power;
                sums.y[j] += power;
                if (mirrored) sums.y[(n - j) % n] += power;
                const int signed_j = 2 * j <= n ? j : j - n;
                const double fy = signed_j * psd.frequency_step_y_per_um;
                const double f = std::sqrt(fx * fx + fy * fy);  // no overflow to guard against: cheaper than hypot
                const int annulus = static_cast<int>(std::lround(f / step));
                sums.radial[annulus] += (mirrored ? 2.0 : 1.0) * power;
                sums.cells[annulus] += mirrored ? 2.0 : 1.0;
            }
        });
    // |F|² dx dy / Σw² is C; the marginals integrate it over the other axis's step.
    const double scale = dx * dy / window_power;
    for (std::size_t k = 0; k < bins_x; ++k) {
        psd.x_frequency_per_um.push_back(k * psd.frequency_step_x_per_um);
        psd.x_um3.push_back(x_power[k] * scale * psd.frequency_step_y_per_um);
    }
    std::vector<double> y_power(rows, 0.0), radial_power(annuli, 0.0), cells(annuli, 0.0);
    for (const BlockPower& sums : partial) {
        for (int j = 0; j < rows; ++j) y_power[j] += sums.y[j];
        for (int b = 0; b < annuli; ++b) radial_power[b] += sums.radial[b], cells[b] += sums.cells[b];
    }
    for (int m = 0; 2 * m <= rows; ++m) {
        psd.y_frequency_per_um.push_back(m * psd.frequency_step_y_per_um);
        // Row index j holds f_y = −j_signed·Δf_y (rows run toward −y); C_y is even, either sign serves.
        psd.y_um3.push_back(y_power[(rows - m) % rows] * scale * psd.frequency_step_x_per_um);
    }
    const double cell_area = psd.frequency_step_x_per_um * psd.frequency_step_y_per_um;
    for (int b = 0; b < annuli; ++b) {
        psd.radial_frequency_per_um.push_back(b * step);
        psd.radial_um4.push_back(cells[b] > 0.0 ? radial_power[b] * scale / cells[b]
                                                : std::numeric_limits<double>::quiet_NaN());
        psd.radial_area_per_um2.push_back(cells[b] * cell_area);
    }
    return psd;
}

AutocorrelationCurves compute_autocorrelation_curves(const Heightfield& field, double threshold) {
    const ValidHeights valid = valid_heights(field, "autocorrelation");
    check_threshold(threshold);
    if (valid.lowest == valid.highest) throw Error("the autocorrelation needs heights that vary (Sq = 0)");
    const double dx = field.dx_um(), dy = field.dy_um();
    const Autocorrelation acf(field, valid);
    AutocorrelationCurves curves;
    curves.parameters.threshold = threshold;
    decay_parameters(acf, dx, dy, curves.parameters);  // Sal as info computes it, from the same f
    for (int c = 0; c <= acf.max_col_lag(); ++c) curves.x_lag_um.push_back(c * dx), curves.x.push_back(acf.at(0, c));
    for (int r = 0; r <= acf.max_row_lag(); ++r)
        curves.y_lag_um.push_back(r * dy), curves.y.push_back(acf.at(-r, 0));  // rows run toward −y
    const double width = std::min(dx, dy);
    const int annuli = static_cast<int>(std::min(acf.max_col_lag() * dx, acf.max_row_lag() * dy) / width) + 1;
    const std::size_t lag_rows = 2 * static_cast<std::size_t>(acf.max_row_lag()) + 1;
    const std::size_t chunks = (lag_rows + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<std::vector<double>> sums(chunks, std::vector<double>(annuli, 0.0)), counts = sums;
    parallel_for(lag_rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        std::vector<double>& sum = sums[begin / kRowsPerChunk];
        std::vector<double>& count = counts[begin / kRowsPerChunk];
        for (std::size_t i = begin; i < end; ++i) {
            const int r = static_cast<int>(i) - acf.max_row_lag();
            for (int c = -acf.max_col_lag(); c <= acf.max_col_lag(); ++c) {
                const double x = c * dx, y = r * dy;
                const int annulus = static_cast<int>(std::lround(std::sqrt(x * x + y * y) / width));
                const double value = acf.at(r, c);
                if (annulus >= annuli || std::isnan(value)) continue;
                sum[annulus] += value;
                count[annulus] += 1.0;
            }
        }
    });
    for (int b = 0; b < annuli; ++b) {
        double sum = 0.0, count = 0.0;
        for (std::size_t chunk = 0; chunk < chunks; ++chunk) sum += sums[chunk][b], count += counts[chunk][b];
        curves.radial_lag_um.push_back(b * width);
        curves.radial.push_back(count > 0.0 ? sum / count : std::numeric_limits<double>::quiet_NaN());
    }
    return curves;
}

}  // namespace glintscope
