#include "glintscope/surface/areal_parameters.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "surface/field_transforms.hpp"
#include "surface/statistics_parts.hpp"

namespace glintscope {
namespace {

using namespace field_transforms;

constexpr int kDirections = 360;    // rays every 0.5° over [0°, 180°): f(t) = f(−t)
constexpr int kAngularBins = 180;   // 1° bins of the angular spectrum
constexpr double kRayStep = 0.25;   // in texels

// ---- height and hybrid parameters ----

struct Deviations {
    double squares = 0.0, cubes = 0.0, fourths = 0.0, absolutes = 0.0;
    double lowest = std::numeric_limits<double>::infinity();
    double highest = -std::numeric_limits<double>::infinity();
    std::size_t gradients = 0;
    double gradient_squares = 0.0;
    double area_excess = 0.0;  // Σ √(1 + |∇z|²) − 1
};

// The height moments of one row about `mean`.
void add_heights(const float* row, int cols, double mean, Deviations& sums) {
    for (int c = 0; c < cols; ++c) {
        const double h = row[c];
        if (std::isnan(h)) continue;
        const double z = h - mean;
        const double z2 = z * z;
        sums.squares += z2;
        sums.cubes += z2 * z;
        sums.fourths += z2 * z2;
        sums.absolutes += std::fabs(z);
        sums.lowest = std::min(sums.lowest, z);
        sums.highest = std::max(sums.highest, z);
    }
}

// The central-difference gradient at column c of a row whose neighbours along y are `above` and
// `below` (row r − 1 is at larger y), from columns `left` and `right`; NaN-free values only.
void add_gradient(const float* row, const float* above, const float* below, int c, int left, int right,
                  double inverse_2dx, double inverse_2dy, Deviations& sums) {
    const double zx = (double(row[right]) - row[left]) * inverse_2dx;
    const double zy = (double(above[c]) - below[c]) * inverse_2dy;
    if (std::isnan(zx) || std::isnan(zy) || std::isnan(row[c])) return;
    const double slope_squared = zx * zx + zy * zy;
    ++sums.gradients;
    sums.gradient_squares += slope_squared;
    // √(1+g²) − 1 written as g² / (√(1+g²) + 1): no cancellation for small slopes.
    sums.area_excess += slope_squared / (std::sqrt(1.0 + slope_squared) + 1.0);
}

// The gradient terms of columns 1..cols−2 of a row: g² = |∇z|² and the area excess
// g² / (√(1+g²) + 1), NaN where a neighbour is missing. A loop without branches, which the
// compiler vectorises (this file is compiled without errno, so the square root can be); square
// roots and divisions are correctly rounded, so the values are the scalar loop's bit for bit.
void interior_gradient_terms(const float* row, const float* above, const float* below, int cols,
                             double inverse_2dx, double inverse_2dy, double* squares, double* excess) {
    for (int c = 1; c + 1 < cols; ++c) {
        const double zx = (double(row[c + 1]) - row[c - 1]) * inverse_2dx;
        const double zy = (double(above[c]) - below[c]) * inverse_2dy;
        const double slope_squared = zx * zx + zy * zy;
        squares[c] = slope_squared;
        excess[c] = slope_squared / (std::sqrt(1.0 + slope_squared) + 1.0);
    }
}

Deviations deviations(const Heightfield& field, double mean, double dx, double dy) {
    const int rows = field.rows;
    const int cols = field.cols;
    const double inverse_2dx = 1.0 / (2.0 * dx), inverse_2dy = 1.0 / (2.0 * dy);
    const std::size_t chunks = (rows + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<Deviations> partial(chunks);
    const auto row_at = [&](int r) { return field.heights_um.data() + static_cast<std::size_t>(r) * cols; };
    parallel_for(rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        Deviations sums;
        for (int r = static_cast<int>(begin); r < static_cast<int>(end); ++r) {
            const float* row = row_at(r);
            add_heights(row, cols, mean, sums);
            const int up = neighbour(r, -1, rows, field.periodic);
            const int down = neighbour(r, 1, rows, field.periodic);
            if (up < 0 || down < 0) continue;
            const float* above = row_at(up);
            const float* below = row_at(down);
            // The border columns have a neighbour only on a periodic field.
            if (field.periodic)
                add_gradient(row, above, below, 0, cols - 1, 1 % cols, inverse_2dx, inverse_2dy, sums);
            // Summed in column order after the vectorised terms: the same sums as add_gradient's.
            double* squares = thread_scratch<double>(0, cols);
            double* excess = thread_scratch<double>(1, cols);
            interior_gradient_terms(row, above, below, cols, inverse_2dx, inverse_2dy, squares, excess);
            for (int c = 1; c + 1 < cols; ++c) {
                if (std::isnan(squares[c]) || std::isnan(row[c])) continue;
                ++sums.gradients;
                sums.gradient_squares += squares[c];
                sums.area_excess += excess[c];
            }
            if (field.periodic && cols > 1)
                add_gradient(row, above, below, cols - 1, cols - 2, 0, inverse_2dx, inverse_2dy, sums);
        }
        partial[begin / kRowsPerChunk] = sums;
    });
    Deviations total;
    for (const Deviations& sums : partial) {
        total.squares += sums.squares;
        total.cubes += sums.cubes;
        total.fourths += sums.fourths;
        total.absolutes += sums.absolutes;
        total.lowest = std::min(total.lowest, sums.lowest);
        total.highest = std::max(total.highest, sums.highest);
        total.gradients += sums.gradients;
        total.gradient_squares += sums.gradient_squares;
        total.area_excess += sums.area_excess;
    }
    return total;
}

struct RayDecay {
    double length_um = 0.0;       // where f first reaches the threshold, or the last lag evaluated
    bool decayed = false;
    double last_value = 1.0;      // f at the last lag evaluated (when it did not decay)
};

// Marches along direction θ (from +x, counter-clockwise, y up) in steps of a quarter texel
// until f falls to `threshold` (linear between steps) or the ray leaves the evaluated lags.
RayDecay decay_along(const Autocorrelation& acf, double theta, double dx, double dy, double threshold) {
    const double step = kRayStep * std::min(dx, dy);
    const double ux = std::cos(theta), uy = std::sin(theta);
    const double max_x = acf.max_col_lag() * dx, max_y = acf.max_row_lag() * dy;
    RayDecay decay;
    double previous = 1.0, previous_r = 0.0;
    for (int k = 1;; ++k) {
        const double r = k * step;
        const double x = r * ux, y = r * uy;
        if (std::fabs(x) > max_x || std::fabs(y) > max_y) break;
        const double value = acf.interpolate(-y / dy, x / dx);  // rows run towards −y
        if (std::isnan(value)) continue;
        if (value <= threshold) {
            decay.decayed = true;
            decay.length_um = previous_r + (previous - threshold) / (previous - value) * (r - previous_r);
            return decay;
        }
        previous = value;
        previous_r = r;
    }
    decay.length_um = previous_r;
    decay.last_value = previous;
    return decay;
}

}  // namespace

void field_transforms::decay_parameters(const Autocorrelation& acf, double dx, double dy, ArealParameters& p) {
    p.max_lag_x_um = acf.max_col_lag() * dx;
    p.max_lag_y_um = acf.max_row_lag() * dy;
    std::vector<RayDecay> rays(kDirections);
    parallel_for(kDirections, 8, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            rays[i] = decay_along(acf, pi * static_cast<double>(i) / kDirections, dx, dy, p.threshold);
    });
    const auto degrees = [](std::size_t i) { return 180.0 * static_cast<double>(i) / kDirections; };
    int fastest = -1, slowest_decayed = -1, slowest_open = -1, fastest_open = -1;
    for (int i = 0; i < kDirections; ++i) {
        if (rays[i].decayed) {
            if (fastest < 0 || rays[i].length_um < rays[fastest].length_um) fastest = i;
            if (slowest_decayed < 0 || rays[i].length_um > rays[slowest_decayed].length_um) slowest_decayed = i;
        } else {
            // Of the directions that do not decay, the slowest keeps the highest autocorrelation
            // at the end of its ray, the fastest the lowest.
            if (slowest_open < 0 || rays[i].last_value > rays[slowest_open].last_value) slowest_open = i;
            if (fastest_open < 0 || rays[i].last_value < rays[fastest_open].last_value) fastest_open = i;
        }
    }
    // Sal: the fastest decay; when no direction decays within the lags, it exceeds the length
    // of the ray that fell furthest.
    const int sal = fastest >= 0 ? fastest : fastest_open;
    p.sal_um = rays[sal].length_um;
    p.sal_is_lower_bound = fastest < 0;
    p.sal_direction_deg = degrees(sal);
    p.sal_autocorrelation_at_edge = rays[sal].decayed ? p.threshold : rays[sal].last_value;
    // The slowest decay: a lower bound when some direction never decays.
    const int longest = slowest_open >= 0 ? slowest_open : slowest_decayed;
    p.longest_decay_um = rays[longest].length_um;
    p.longest_is_lower_bound = slowest_open >= 0;
    p.longest_direction_deg = degrees(longest);
    p.longest_autocorrelation_at_edge = rays[longest].decayed ? p.threshold : rays[longest].last_value;
    p.str = p.sal_um / p.longest_decay_um;
    p.str_is_upper_bound = p.longest_is_lower_bound && !p.sal_is_lower_bound;
}

void field_transforms::check_threshold(double threshold) {
    if (!(threshold > 0.0 && threshold < 1.0))
        throw Error("the autocorrelation threshold s must lie between 0 and 1, got " + shortest_text(threshold));
}

namespace {

// ---- texture direction ----

// Tile origins along an axis of n samples: whole tiles from 0, and one more ending at n when
// they do not cover it.
std::vector<int> tile_starts(int n, int tile) {
    std::vector<int> starts;
    for (int start = 0; start + tile <= n; start += tile) starts.push_back(start);
    if (starts.back() + tile < n) starts.push_back(n - tile);
    return starts;
}

// The angular power spectrum, from the power spectra of tiles of at most kSpectrumTile² samples
// averaged (Welch's method: the binning then runs once over one tile's frequencies, and the
// average is smoother than one large periodogram). Each tile is Hann-windowed so that its
// borders do not paint a cross on the spectrum, except a tile that is a whole periodic field.
constexpr int kSpectrumTile = 1024;

double texture_direction_deg(const Heightfield& field, double mean, double dx, double dy) {
    const int rows = std::min(field.rows, kSpectrumTile), cols = std::min(field.cols, kSpectrumTile);
    const bool whole_tile = field.periodic && rows == field.rows && cols == field.cols;
    std::vector<float> window_x(cols, 1.0f), window_y(rows, 1.0f);
    if (!whole_tile) {
        for (int c = 0; c < cols; ++c) window_x[c] = static_cast<float>(std::pow(std::sin(pi * (c + 0.5) / cols), 2));
        for (int r = 0; r < rows; ++r) window_y[r] = static_cast<float>(std::pow(std::sin(pi * (r + 0.5) / rows), 2));
    }
    const int bins_x = cols / 2 + 1;
    std::vector<double> power(static_cast<std::size_t>(bins_x) * rows, 0.0);  // [k][j]
    for (const int top : tile_starts(field.rows, rows))
        for (const int left : tile_starts(field.cols, cols))
            forward_2d(
                rows, cols, rows,
                [&](int r, float* out) {
                    for (int c = 0; c < cols; ++c) {
                        const float h = field.at(top + r, left + c);
                        out[c] = std::isnan(h) ? 0.0f : static_cast<float>(h - mean) * window_x[c] * window_y[r];
                    }
                },
                [&](std::size_t k, fftwf_complex* column, int n, std::size_t) {
                    double* into = power.data() + k * n;
                    for (int j = 0; j < n; ++j) into[j] += double(column[j][0]) * column[j][0] + double(column[j][1]) * column[j][1];
                });
    // Each frequency cell's power is spread over the angles the cell subtends (about its width over
    // its radius): binned by its centre alone, the few cells near the origin, which carry most of
    // the power, would crowd the axes' and diagonals' bins and give an isotropic surface a lay.
    const double cell = std::sqrt(1.0 / (cols * dx) / (rows * dy));
    std::array<double, kAngularBins> spectrum{};
    const auto deposit = [&spectrum](double angle, double half_width, double value) {
        const double low = angle - half_width, high = angle + half_width;
        for (int b = static_cast<int>(std::floor(low + 0.5)); b <= static_cast<int>(std::floor(high + 0.5)); ++b) {
            const double overlap = std::min(high, b + 0.5) - std::max(low, b - 0.5);
            if (overlap > 0.0) spectrum[((b % kAngularBins) + kAngularBins) % kAngularBins] += value * overlap / (high - low);
        }
    };
    for (int k = 0; k < bins_x; ++k) {
        // Each k > 0 below the Nyquist column also stands for its mirror −k.
        const double weight = (k == 0 || 2 * k == cols) ? 1.0 : 2.0;
        const double u = k / (0.5 * cols);
        for (int j = 0; j < rows; ++j) {
            const int row_frequency = j <= rows / 2 ? j : j - rows;
            const double v = row_frequency / (0.5 * rows);
            if ((k == 0 && row_frequency == 0) || u * u + v * v > 1.0) continue;
            const double fx = k / (cols * dx);
            const double fy = -row_frequency / (rows * dy);  // rows run towards −y
            double angle = std::atan2(fy, fx) * 180.0 / pi;
            if (angle < 0.0) angle += 180.0;
            const double half_width = std::min(90.0, 0.5 * cell / std::hypot(fx, fy) * 180.0 / pi);
            deposit(angle, half_width, weight * power[k * rows + j]);
        }
    }
    const int peak = static_cast<int>(std::max_element(spectrum.begin(), spectrum.end()) - spectrum.begin());
    // A parabola through the peak bin and its (circular) neighbours places the maximum between bins.
    const double before = spectrum[(peak + kAngularBins - 1) % kAngularBins];
    const double after = spectrum[(peak + 1) % kAngularBins];
    const double curvature = before - 2.0 * spectrum[peak] + after;
    const double shift = curvature < 0.0 ? 0.5 * (before - after) / curvature : 0.0;
    double lay = peak + shift + 90.0;  // the lay runs perpendicular to the spectrum's maximum
    while (lay > 90.0) lay -= 180.0;
    while (lay <= -90.0) lay += 180.0;
    return lay;
}

// The height and hybrid parameters, with the threshold set (the spatial ones follow).
ArealParameters height_and_hybrid_parameters(const Heightfield& field, const ValidHeights& valid, double threshold) {
    const double dx = field.dx_um(), dy = field.dy_um();
    const Deviations d = deviations(field, valid.mean, dx, dy);
    const double n = static_cast<double>(valid.count);
    ArealParameters p;
    p.threshold = threshold;
    p.sq_um = std::sqrt(d.squares / n);
    if (!(p.sq_um > 0.0)) throw Error("areal parameters need heights that vary (Sq = 0)");
    p.ssk = d.cubes / n / (p.sq_um * p.sq_um * p.sq_um);  // ISO 25178-2 §4.1.3
    p.sku = d.fourths / n / (p.sq_um * p.sq_um * p.sq_um * p.sq_um);  // ISO 25178-2 §4.1.4
    p.sp_um = d.highest;
    p.sv_um = -d.lowest;
    p.sz_um = p.sp_um + p.sv_um;
    p.sa_um = d.absolutes / n;
    if (d.gradients == 0) throw Error("areal parameters need valid slopes (no valid point has valid neighbours)");
    p.sdq = std::sqrt(d.gradient_squares / static_cast<double>(d.gradients));  // ISO 25178-2 §4.3.1
    p.sdr = d.area_excess / static_cast<double>(d.gradients);                     // ISO 25178-2 §4.3.2
    return p;
}

// Sal, Str (from the autocorrelation) and Std.
void add_spatial_parameters(const Heightfield& field, const ValidHeights& valid, const Autocorrelation& acf,
                            ArealParameters& p) {
    decay_parameters(acf, field.dx_um(), field.dy_um(), p);
    p.std_deg = texture_direction_deg(field, valid.mean, field.dx_um(), field.dy_um());
}

// Slopes need both neighbours, which a non-periodic field smaller than 3 × 3 lacks.
bool too_small_for_slopes(const Heightfield& field) {
    return !field.periodic && (field.rows < 3 || field.cols < 3);
}

void check_field_size(const Heightfield& field) {
    if (too_small_for_slopes(field))
        throw Error("areal parameters need at least 3 x 3 samples (slopes need both neighbours)");
}

}  // namespace

ArealParameters compute_areal_parameters(const Heightfield& field, double threshold) {
    const ValidHeights valid = valid_heights(field, "areal parameters");
    check_threshold(threshold);
    check_field_size(field);
    ArealParameters p = height_and_hybrid_parameters(field, valid, threshold);
    add_spatial_parameters(field, valid, Autocorrelation(field, valid), p);
    return p;
}

SurfaceReport compute_surface_report(const Heightfield& field, double threshold) {
    check_threshold(threshold);
    const ValidHeights valid = validated_heights(field, "statistics", /*allow_missing=*/true);
    SurfaceReport report;
    report.statistics = statistics_without_correlation(field, valid);
    if (!(report.statistics.sq_um > 0.0))
        report.iso_undefined = "the heights do not vary";
    else if (too_small_for_slopes(field))
        report.iso_undefined = "fewer than 3 x 3 samples";
    if (!report.iso_undefined.empty()) {
        line_correlation_lengths(field, report.statistics);
        return report;
    }
    ArealParameters p = height_and_hybrid_parameters(field, valid, threshold);
    const Autocorrelation acf(field, valid);
    read_correlation_lengths(acf, field.dx_um(), field.dy_um(), report.statistics);
    add_spatial_parameters(field, valid, acf, p);
    report.iso = p;
    return report;
}

}  // namespace glintscope
