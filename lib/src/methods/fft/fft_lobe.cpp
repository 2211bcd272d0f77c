#include "fft_lobe.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include "numerics/chirp_z.hpp"
#include "wave/footprint_grid.hpp"
#include "wave/xi3_slices.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {
namespace {

// Work-size limits: beyond them the method refuses with a message instead of exhausting memory.
constexpr int kMaxSamplesPerAxis = 16384;
// The footprint grid's working arrays per sample (heights, slopes, weights, the transformed rows):
// about 35 bytes measured (peak RSS of σ_c = 10 and 20 µm lobes), with headroom.
constexpr double kBytesPerSample = 40.0;
constexpr int kMaxXi3Slices = 4096;

}  // namespace

FftSettings fft_settings(const LobeQuery& query) {
    FftSettings settings;
    if (query.method_options.count("step")) {
        settings.step_um = method_option_length_um(query, "step", 0.0);
        if (!(settings.step_um > 0.0))
            throw Error("option step must be a positive length, got '" + query.method_options.at("step") + "'");
    }
    settings.window_sigmas = method_option_number(query, "window", settings.window_sigmas);
    if (!(settings.window_sigmas >= 1.0 && settings.window_sigmas <= 20.0))
        throw Error("option window must be between 1 and 20 coherence sigmas, got " +
                    shortest_text(settings.window_sigmas));
    const bool box = query.footprint.shape == FootprintShape::box;
    settings.guard_widths = method_option_number(query, "guard", box ? 32.0 : 6.0);
    if (!(settings.guard_widths >= 1.0 && settings.guard_widths <= 1000.0))
        throw Error("option guard must be between 1 and 1000 footprint spectral widths, got " +
                    shortest_text(settings.guard_widths));
    settings.oversampling = method_option_number(query, "oversampling", settings.oversampling);
    if (!(settings.oversampling >= 1.0 && settings.oversampling <= 100.0))
        throw Error("option oversampling must be between 1 and 100, got " + shortest_text(settings.oversampling));
    settings.phase_error = method_option_number(query, "phase_error", settings.phase_error);
    if (!(settings.phase_error > 0.0 && settings.phase_error <= 1.0))
        throw Error("option phase_error must be in (0, 1], got " + shortest_text(settings.phase_error));
    const std::string edge = method_option_text(query, "edge", "refuse");
    if (edge != "refuse" && edge != "truncate") throw Error("option edge must be refuse or truncate, got '" + edge + "'");
    settings.truncate_at_edges = edge == "truncate" && !query.field->periodic;
    return settings;
}

namespace {

// One sub-row b of the K×K supersampling: N rows × K·N columns, column m = c·K + a being
// sub-column a of pixel column c. Positions are regular along rows and columns, so ψ̄/λ is too.
struct SubpixelGrid {
    int rows = 0;
    int cols = 0;
    std::vector<Vec3> omega_o;
    std::vector<Vec3> psi;              // geometry.offset + geometry.scale·ω_o
    std::vector<unsigned char> inside;  // inside the unit disk, i.e. above the horizon
};

SubpixelGrid subpixel_grid(int resolution, int supersample, int sub_row, const ScatteringGeometry& geometry) {
    SubpixelGrid grid;
    grid.rows = resolution;
    grid.cols = resolution * supersample;
    grid.omega_o.resize(static_cast<std::size_t>(grid.rows) * grid.cols);
    grid.psi.resize(grid.omega_o.size());
    grid.inside.resize(grid.omega_o.size());
    const double dv = subpixel_offset(sub_row, supersample);
    for (int r = 0; r < grid.rows; ++r)
        for (int m = 0; m < grid.cols; ++m) {
            const DiskPoint p = disk_pixel_point(r, m / supersample, resolution,
                                                 subpixel_offset(m % supersample, supersample), dv);
            const std::size_t i = static_cast<std::size_t>(r) * grid.cols + m;
            grid.inside[i] = inside_unit_disk(p);
            grid.omega_o[i] = direction_from_disk(p.x, p.y);
            grid.psi[i] = geometry.offset + geometry.scale * grid.omega_o[i];
        }
    return grid;
}

// Everything one wavelength's transforms share.
struct WavelengthSetup {
    const LobeQuery* query = nullptr;
    ScatteringGeometry geometry;
    double lambda_um = 0.0;
    FootprintSamples samples;
    Xi3Slices slices;
    // e^{−i2π Δξ (H − H̄)/λ} per sample, Δξ the node spacing: stepping R* from one ξ3 node to the
    // next by one multiplication instead of a sincos (GHS, R-GHS, Kirchhoff only).
    std::vector<Complex> node_step;
    const ReflectionSource* source = nullptr;  // else the exact R*
};

// e^{−i2π ξ (H(s) − H̄)/λ} at every sample, times w(s − x_c) if `weighted`: then it is R*(s) of
// Yan 2018 eq. 1, 4 (ξ2 is applied later).
std::vector<Complex> phase_factors(const WavelengthSetup& setup, double xi, bool weighted) {
    const FootprintSamples& samples = setup.samples;
    const double phase_per_height = -2.0 * pi * xi / setup.lambda_um;
    std::vector<Complex> factors(samples.weight.size());
    parallel_for(factors.size(), 4096, [&](std::size_t begin, std::size_t end) {
        for (std::size_t s = begin; s < end; ++s)
            factors[s] = std::polar(weighted ? samples.weight[s] : 1.0, phase_per_height * samples.height[s]);
    });
    return factors;
}

// Which ξ3 nodes each sub-column needs, and every sub-pixel's ξ3.
struct NodeUse {
    std::vector<double> xi3_at;
    std::vector<int> lowest_node;
    std::vector<int> highest_node;
};

NodeUse node_use(const WavelengthSetup& setup, const SubpixelGrid& grid) {
    const LobeQuery& query = *setup.query;
    NodeUse use{std::vector<double>(grid.omega_o.size()), std::vector<int>(grid.cols, INT_MAX),
                std::vector<int>(grid.cols, INT_MIN)};
    for (int r = 0; r < grid.rows; ++r)
        for (int m = 0; m < grid.cols; ++m) {
            const std::size_t i = static_cast<std::size_t>(r) * grid.cols + m;
            if (!grid.inside[i]) continue;
            use.xi3_at[i] = phase_depends_on_outgoing(query.model) ? grid.psi[i].z : 2.0;  // Yan 2018 Fig. 6: ψ·n or 2
            use.lowest_node[m] = std::min(use.lowest_node[m], setup.slices.lowest_node(use.xi3_at[i]));
            use.highest_node[m] = std::max(use.highest_node[m], setup.slices.highest_node(use.xi3_at[i]));
        }
    return use;
}

// Yan 2018 Fig. 6: the Kirchhoff ξ2 = 1 − ψ̄·H'/(ψ·n) is linear in H', so
// R̃* = T0 − (ψ̄_x T_x + ψ̄_y T_y)/(ψ·n) with T0 = F[R*], T_x = F[H_x R*], T_y = F[H_y R*].
int component_count(DiffractionModel model) { return model == DiffractionModel::kirchhoff ? 3 : 1; }

// First pass: every sample row (and component) transformed along x to all K·N sub-columns, stored
// column-major (result[(c·cols + m)·ny + k]) for the second pass; ny rows (the grid's, or its
// rows folded along y). Rows go in blocks of 8 so that the transposed writes fill whole cache
// lines.
// `parts` holds the Kirchhoff components H_x R*, H_y R* when a source gave them; otherwise they
// are formed from R* and the grid's slopes.
void transform_rows(const WavelengthSetup& setup, const std::vector<Complex>& reflection,
                    const std::vector<std::vector<Complex>>& parts, const ChirpZ& along_x, int cols, int ny,
                    std::vector<Complex>& result) {
    const FootprintSamples& samples = setup.samples;
    const int nx = samples.x.count;
    const int components = component_count(setup.query->model);
    constexpr std::size_t block = 8;
    parallel_for(ny, block, [&](std::size_t begin, std::size_t end) {
        auto workspace = along_x.make_workspace();
        // Scratch kept by the thread: every element is written before it is read.
        Complex* formed = thread_scratch<Complex>(0, nx);
        Complex* output = thread_scratch<Complex>(1, block * components * cols);
        for (std::size_t k = begin; k < end; ++k)
            for (int c = 0; c < components; ++c) {
                const Complex* row = &reflection[k * nx];
                const Complex* input = row;
                if (c > 0 && parts.size() > static_cast<std::size_t>(c)) {
                    input = &parts[c][k * nx];
                } else if (c > 0) {  // H_x R* or H_y R* from the grid's slopes
                    const double* slope = &(c == 1 ? samples.slope_x : samples.slope_y)[k * nx];
                    for (int j = 0; j < nx; ++j) formed[j] = row[j] * slope[j];
                    input = formed;
                }
                along_x.transform(input, &output[((k - begin) * components + c) * cols], workspace.get());
            }
        for (int c = 0; c < components; ++c)
            for (int m = 0; m < cols; ++m)
                for (std::size_t k = begin; k < end; ++k)
                    result[(static_cast<std::size_t>(c) * cols + m) * ny + k] =
                        output[((k - begin) * components + c) * cols + m];
    });
}

// Second pass: each listed sub-column transformed along y to all N rows; each sub-pixel adds
// this node's R̃* with its interpolation weight at its own ξ3.
void transform_columns(const WavelengthSetup& setup, const SubpixelGrid& grid, const NodeUse& use, int node,
                       const std::vector<int>& columns, const std::vector<Complex>& rows_result,
                       const ChirpZ& along_y, std::vector<Complex>& field) {
    const LobeQuery& query = *setup.query;
    const int ny = along_y.input_count();
    const int components = component_count(query.model);
    parallel_for(columns.size(), 8, [&](std::size_t begin, std::size_t end) {
        auto workspace = along_y.make_workspace();
        std::vector<Complex> output(static_cast<std::size_t>(components) * grid.rows);
        for (std::size_t index = begin; index < end; ++index) {
            const int m = columns[index];
            for (int c = 0; c < components; ++c)
                along_y.transform(&rows_result[(static_cast<std::size_t>(c) * grid.cols + m) * ny],
                                  &output[static_cast<std::size_t>(c) * grid.rows], workspace.get());
            for (int r = 0; r < grid.rows; ++r) {
                const std::size_t i = static_cast<std::size_t>(r) * grid.cols + m;
                if (!grid.inside[i]) continue;
                const double weight = setup.slices.weight(node, use.xi3_at[i]);
                if (weight == 0.0) continue;
                Complex value = output[r];
                if (components == 3) {
                    const Vec3 psi = grid.psi[i];
                    value -= (psi.x * output[grid.rows + r] + psi.y * output[2 * grid.rows + r]) / psi.z;
                }
                field[i] += weight * value;
            }
        }
    });
}

// Adds grid row x times `modulation` to folded row out[0], and with kSlopes the same times H_x
// and H_y to out[1], out[2]: one pass over the row. With kStep, x (R*) is first stepped to the
// next ξ3 node and written back to `stepped` (x itself).
template <bool kStep, bool kSlopes>
void fold_row(const Complex* x, Complex* stepped, const Complex* __restrict step, const double* __restrict slope_x,
              const double* __restrict slope_y, Complex modulation, int nx, Complex* const* out) {
    Complex* __restrict out0 = out[0];
    Complex* __restrict out1 = out[1];
    Complex* __restrict out2 = out[2];
    for (int j = 0; j < nx; ++j) {
        Complex value = x[j];
        if constexpr (kStep) {
            value = multiply(value, step[j]);
            stepped[j] = value;
        }
        const Complex modulated = multiply(value, modulation);
        out0[j] += modulated;
        if constexpr (kSlopes) {
            out1[j] += modulated * slope_x[j];
            out2[j] += modulated * slope_y[j];
        }
    }
}

// The grid's rows folded along y for a transform that folds (chirp_z.hpp): row r of component c is
// Σ_{k ≡ r (mod F)} e^{−i2π k h v0} x_c[k], x_c the rows of R*, H_x R*, H_y R* (or of `parts`),
// so that the rows pass transforms F rows instead of the grid's and the columns need no fold.
// Each folded row adds its grid rows in order, whatever the thread. With `step`, R* is first
// stepped to the next ξ3 node in place (R* ← R*·step), in the same pass.
void fold_rows(const WavelengthSetup& setup, std::vector<Complex>& reflection,
               const std::vector<std::vector<Complex>>& parts, const ChirpZ& along_y, const Complex* step,
               std::vector<std::vector<Complex>>& folded) {
    const FootprintSamples& samples = setup.samples;
    const int nx = samples.x.count;
    const int ny = samples.y.count;
    const int fold = along_y.fold_size();
    const int components = component_count(setup.query->model);
    const bool from_parts = parts.size() > 1;  // a source's Kirchhoff components
    folded.resize(static_cast<std::size_t>(components));
    for (std::vector<Complex>& rows : folded) rows.resize(static_cast<std::size_t>(fold) * nx);
    parallel_for(fold, 4, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            Complex* out[3];
            for (int c = 0; c < 3; ++c) out[c] = c < components ? &folded[c][r * nx] : nullptr;
            for (int c = 0; c < components; ++c) std::fill_n(out[c], nx, Complex(0.0, 0.0));
            for (std::size_t k = r; k < static_cast<std::size_t>(ny); k += fold) {
                const Complex modulation = along_y.modulation(static_cast<int>(k));
                Complex* row = &reflection[k * nx];
                const Complex* row_step = step ? &step[k * nx] : nullptr;
                if (components == 1 || from_parts) {
                    if (row_step)
                        fold_row<true, false>(row, row, row_step, nullptr, nullptr, modulation, nx, out);
                    else
                        fold_row<false, false>(row, nullptr, nullptr, nullptr, nullptr, modulation, nx, out);
                    for (int c = 1; c < components; ++c) {
                        Complex* part_out[3] = {out[c], nullptr, nullptr};
                        fold_row<false, false>(&parts[c][k * nx], nullptr, nullptr, nullptr, nullptr, modulation, nx,
                                               part_out);
                    }
                } else if (row_step) {
                    fold_row<true, true>(row, row, row_step, &samples.slope_x[k * nx], &samples.slope_y[k * nx],
                                         modulation, nx, out);
                } else {
                    fold_row<false, true>(row, nullptr, nullptr, &samples.slope_x[k * nx], &samples.slope_y[k * nx],
                                          modulation, nx, out);
                }
            }
        }
    });
}

// One sub-row b of the K×K supersampling: its sub-pixels, the ξ3 nodes they need, its transform
// along y, and R̃* at its sub-pixels as the nodes add up.
struct SubRow {
    SubpixelGrid grid;
    NodeUse use;
    ChirpZ along_y;
    std::vector<Complex> field;
};

// R̃*(ψ̄/λ) at every sub-pixel of every sub-row, by chirp-z transforms along x (each sample row to
// all K·N sub-columns, once per ξ3 node for all sub-rows: their sub-columns are the same) and then
// along y (each sub-row's needed sub-columns to its N rows), summed over the ξ3 nodes with each
// sub-pixel's interpolation weights. Each value is correct up to the unit factor e^{−i2π s_0·v}
// of the grid origin s_0, common to every node and Kirchhoff component at that v and so invisible
// in |R̃*|². The cell area is not applied.
void transform_fields(const WavelengthSetup& setup, const ChirpZ& along_x, std::vector<SubRow>& sub_rows) {
    const Xi3Slices& slices = setup.slices;
    const int cols = sub_rows.front().grid.cols;
    // One sub-row whose transform along y folds: its rows are folded first (fold_rows), and the
    // columns take the plain DFT of the F folded rows.
    const ChirpZ& along_y = sub_rows.front().along_y;
    const bool fold_first = sub_rows.size() == 1 && along_y.fold_size() > 0 &&
                            along_y.fold_size() < setup.samples.y.count;
    std::optional<ChirpZ> folded_along_y;
    if (fold_first)
        folded_along_y.emplace(along_y.fold_size(), along_y.output_count(), setup.samples.y.step_um, 0.0,
                               along_y.frequency_step());
    const int rows = fold_first ? along_y.fold_size() : setup.samples.y.count;
    std::vector<Complex> rows_result(static_cast<std::size_t>(component_count(setup.query->model)) * cols * rows);
    std::vector<std::vector<Complex>> parts;  // a source's components
    std::vector<std::vector<Complex>> folded;
    std::vector<Complex> reflection;
    if (!setup.source) reflection = phase_factors(setup, slices.node(slices.first), true);
    std::vector<std::vector<int>> columns(sub_rows.size());
    for (int node = slices.first; node <= slices.last; ++node) {
        bool needed = false;
        for (std::size_t b = 0; b < sub_rows.size(); ++b) {
            const NodeUse& use = sub_rows[b].use;
            columns[b].clear();
            for (int m = 0; m < cols; ++m)
                if (use.lowest_node[m] <= node && node <= use.highest_node[m]) columns[b].push_back(m);
            needed = needed || !columns[b].empty();
        }
        // R* steps to this node here, or in fold_rows's pass over the rows when that runs.
        const bool step_now = !setup.source && node > slices.first;
        if (step_now && !(fold_first && needed))
            parallel_for(reflection.size(), 4096, [&](std::size_t begin, std::size_t end) {
                for (std::size_t s = begin; s < end; ++s)
                    reflection[s] = multiply(reflection[s], setup.node_step[s]);
            });
        if (!needed) continue;
        if (setup.source) {
            setup.source->fill(setup.samples, slices.node(node), setup.lambda_um, parts);
            reflection.swap(parts[0]);
        }
        if (fold_first) {
            fold_rows(setup, reflection, parts, along_y, step_now ? setup.node_step.data() : nullptr, folded);
            transform_rows(setup, folded[0], folded, along_x, cols, rows, rows_result);
        } else {
            transform_rows(setup, reflection, parts, along_x, cols, rows, rows_result);
        }
        if (setup.source) reflection.swap(parts[0]);
        for (std::size_t b = 0; b < sub_rows.size(); ++b)
            if (!columns[b].empty())
                transform_columns(setup, sub_rows[b].grid, sub_rows[b].use, node, columns[b], rows_result,
                                  fold_first ? *folded_along_y : sub_rows[b].along_y, sub_rows[b].field);
    }
}

// Adds to pixel_sums, for each pixel, the sum over the sub-row's sub-pixels of
// factor(ψ, ω_o, λ) · |R̃*(ψ̄/λ)|² / (A_c λ²) (Yan 2018 eq. 6 with ξ1 = factor/λ²).
void add_subpixel_values(const WavelengthSetup& setup, const SubpixelGrid& grid, const std::vector<Complex>& field,
                         double area_um2, const ScatteringFactor& factor, std::vector<double>& pixel_sums) {
    const double cell_area = setup.samples.x.step_um * setup.samples.y.step_um;
    const double scale = cell_area * cell_area / (area_um2 * setup.lambda_um * setup.lambda_um);
    const int supersample = grid.cols / grid.rows;
    parallel_for(grid.rows, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < grid.rows; ++c) {
                double sum = 0.0;
                for (int a = 0; a < supersample; ++a) {
                    const std::size_t i = r * grid.cols + static_cast<std::size_t>(c) * supersample + a;
                    if (!grid.inside[i]) continue;
                    sum += factor(grid.psi[i], grid.omega_o[i], setup.lambda_um) * std::norm(field[i]);
                }
                pixel_sums[r * grid.rows + c] += scale * sum;
            }
    });
}

struct SlopeBound {
    double x = 0.0;
    double y = 0.0;
};

// Finer grids find slightly steeper points between the coarse ones; a slope estimate is padded
// by this factor so that the final grid rarely has to be redone.
constexpr double kSlopePadding = 1.02;

// max |∂H/∂x|, max |∂H/∂y| over the footprint from a grid at a quarter texel (at most 1024
// cells across), padded; sample_for_wavelength checks them on the final grid.
SlopeBound footprint_slopes(const BicubicInterpolant& surface, const FootprintExtent& extent) {
    const double widest = std::max(extent.half_width_um.x, extent.half_width_um.y);
    const double step = std::max(0.25 * std::min(surface.texel_um(), surface.texel_y_um()), 2.0 * widest / 1024.0);
    const FootprintSamples coarse =
        sample_footprint(surface, extent, sample_axis(extent, true, step, kMaxSamplesPerAxis),
                         sample_axis(extent, false, step, kMaxSamplesPerAxis), false);
    return {kSlopePadding * coarse.max_slope_x, kSlopePadding * coarse.max_slope_y};
}

std::string gigabytes(double bytes) { return shortest_text(std::ceil(bytes / 1e8) / 10.0) + " GB"; }

std::size_t samples_in_budget(const LobeQuery& query) {
    return static_cast<std::size_t>(query.memory_budget_gb * 1e9 / kBytesPerSample);
}

bool fits_budget(const LobeQuery& query, const FootprintExtent& extent, double step_x, double step_y) {
    const SampleAxis x = sample_axis(extent, true, step_x, kMaxSamplesPerAxis);
    const SampleAxis y = sample_axis(extent, false, step_y, kMaxSamplesPerAxis);
    return static_cast<std::size_t>(x.count) * y.count <= samples_in_budget(query);
}

FootprintSamples sample_on_axes(const LobeQuery& query, const FootprintExtent& extent, double step_x,
                                double step_y) {
    const SampleAxis x = sample_axis(extent, true, step_x, kMaxSamplesPerAxis);
    const SampleAxis y = sample_axis(extent, false, step_y, kMaxSamplesPerAxis);
    const double count = double(x.count) * y.count;
    if (count > double(samples_in_budget(query)))
        throw Error("the footprint grid would need " + std::to_string(x.count) + "x" + std::to_string(y.count) +
                    " samples, about " + gigabytes(count * kBytesPerSample) + ", beyond the memory budget of " +
                    shortest_text(query.memory_budget_gb) + " GB (--memory); use a larger step or a smaller footprint");
    return sample_footprint(*query.surface, extent, x, y, query.model == DiffractionModel::kirchhoff);
}

// The image's period along x and y, 1/Δv of its sub-pixel grid in ψ̄/λ (fill_layer), which the
// automatic steps divide; zero for a box footprint, whose grid is its cells.
struct ImagePeriods {
    double x_um = 0.0;
    double y_um = 0.0;
};

ImagePeriods image_periods(const LobeQuery& query, const ScatteringGeometry& geometry, double lambda_um) {
    if (query.footprint.shape == FootprintShape::box) return {};  // its grid is the box's cells
    const double row = query.resolution * lambda_um / (2.0 * geometry.scale);
    return {row * std::max(query.supersample, 1), row};
}

// The largest step h ≤ alias_free with period/h a fast FFT size, so that the chirp-z transforms
// fold (chirp_z.hpp); alias_free itself when there is no period.
double commensurate_step(double alias_free, double period_um) {
    if (!(period_um > 0.0)) return alias_free;
    const double bins = std::ceil(period_um / alias_free);
    if (!(bins < kMaxSamplesPerAxis)) return alias_free;
    return period_um / smooth_fft_size(static_cast<int>(bins));
}

// The footprint sampled at the requested step, or at the alias-free step of each axis made
// commensurate with the image's periods (when it has them); if the final grid finds steeper
// slopes than the estimate, the step is recomputed with them.
FootprintSamples sample_for_wavelength(const LobeQuery& query, const ScatteringGeometry& geometry,
                                       const FootprintExtent& extent, const FftSettings& settings, double lambda_um,
                                       double xi3_max, SlopeBound slopes, const ReflectionSource* source,
                                       ImagePeriods periods, double& oversampling_used) {
    if (settings.step_um > 0.0) return sample_on_axes(query, extent, settings.step_um, settings.step_um);
    const double guard = settings.guard_widths * extent.spectral_width + (source ? source->bandwidth : 0.0);
    double q = source && source->smooth ? 1.0 : settings.oversampling;
    const double psi_max_x = std::fabs(geometry.offset.x) + geometry.scale;
    const double psi_max_y = std::fabs(geometry.offset.y) + geometry.scale;
    const auto step_x = [&](double oversampling) {
        return commensurate_step(alias_free_step(psi_max_x, xi3_max, slopes.x, lambda_um, guard, oversampling),
                                 periods.x_um);
    };
    const auto step_y = [&](double oversampling) {
        return commensurate_step(alias_free_step(psi_max_y, xi3_max, slopes.y, lambda_um, guard, oversampling),
                                 periods.y_um);
    };
    // Over the memory budget, the oversampling beyond the alias-free bound goes first (it only
    // pushes the C¹ interpolant's spectral tails further out); the bound itself is kept.
    const auto fits = [&](double oversampling) {
        return fits_budget(query, extent, step_x(oversampling), step_y(oversampling));
    };
    if (q > 1.0 && !fits(q)) {
        double lowered = 1.0;
        while (lowered * 1.25 < q && fits(lowered * 1.25)) lowered *= 1.25;
        q = std::round(lowered * 100) / 100;
    }
    oversampling_used = q;
    for (int attempt = 0;; ++attempt) {
        FootprintSamples samples = sample_on_axes(query, extent, step_x(q), step_y(q));
        const bool covered = samples.max_slope_x <= slopes.x && samples.max_slope_y <= slopes.y;
        if (covered || attempt == 2) return samples;
        slopes = {std::max(slopes.x, kSlopePadding * samples.max_slope_x),
                  std::max(slopes.y, kSlopePadding * samples.max_slope_y)};
    }
}

// How many sub-rows share one pass along x: all of them, unless their sub-pixel arrays (about
// 80 bytes per sub-pixel: directions, ψ, node use, R̃*) would take more than a quarter of the
// memory budget.
int sub_rows_per_batch(const LobeQuery& query) {
    constexpr double kBytesPerSubpixel = 80.0;
    const double sub_row_bytes = kBytesPerSubpixel * double(query.resolution) * query.resolution * query.supersample;
    const double fitting = std::floor(0.25 * query.memory_budget_gb * 1e9 / sub_row_bytes);
    return static_cast<int>(std::clamp(fitting, 1.0, double(query.supersample)));
}

// Fills image layer `layer` from the wavelength's samples: for each sub-row of the K×K
// supersampling, R̃* at its sub-pixels and their f_r, averaged per pixel.
void fill_layer(const WavelengthSetup& setup, const FootprintExtent& extent, const ScatteringFactor& factor,
                LobeImage& image, std::size_t layer) {
    const LobeQuery& query = *setup.query;
    const FootprintSamples& samples = setup.samples;
    const int resolution = query.resolution;
    const int supersample = query.supersample;
    const double lambda = setup.lambda_um;
    // v = ψ̄/λ on the sub-pixel grid: v_x = (o_x + k·x_m)/λ with x_m = (m + 1/2)·2/(K·N) − 1, and
    // v_y = (o_y + k·y_r)/λ with y_r = 1 − (r + 1/2 + dv)·2/N (conventions.md "Frames and images"),
    // o and k the geometry's offset and scale (a lobe: ω_i and 1).
    const ScatteringGeometry& geometry = setup.geometry;
    const double first_x = disk_pixel_point(0, 0, resolution, subpixel_offset(0, supersample)).x;
    const ChirpZ along_x(samples.x.count, resolution * supersample, samples.x.step_um,
                         (geometry.offset.x + geometry.scale * first_x) / lambda,
                         geometry.scale * 2.0 / (resolution * supersample * lambda));
    std::vector<double> pixel_sums(static_cast<std::size_t>(resolution) * resolution);
    const int batch = sub_rows_per_batch(query);
    for (int first = 0; first < supersample; first += batch) {
        std::vector<SubRow> sub_rows;
        for (int sub_row = first; sub_row < std::min(first + batch, supersample); ++sub_row) {
            const double first_y = disk_pixel_point(0, 0, resolution, 0.0, subpixel_offset(sub_row, supersample)).y;
            SubpixelGrid grid = subpixel_grid(resolution, supersample, sub_row, geometry);
            NodeUse use = node_use(setup, grid);
            const std::size_t size = grid.omega_o.size();
            sub_rows.push_back({std::move(grid), std::move(use),
                                ChirpZ(samples.y.count, resolution, samples.y.step_um,
                                       (geometry.offset.y + geometry.scale * first_y) / lambda,
                                       -geometry.scale * 2.0 / (resolution * lambda)),
                                std::vector<Complex>(size)});
        }
        transform_fields(setup, along_x, sub_rows);
        for (const SubRow& sub_row : sub_rows)
            add_subpixel_values(setup, sub_row.grid, sub_row.field, extent.area_um2, factor, pixel_sums);
    }
    store_subpixel_means(image, layer, pixel_sums, supersample);
}

// What the method chose for each wavelength, as metadata lists (one entry per layer, ';'-separated).
struct GridRecord {
    std::vector<std::string> steps, grids, slopes, slices;

    void add(const WavelengthSetup& setup) {
        const FootprintSamples& samples = setup.samples;
        steps.push_back(shortest_text(samples.x.step_um) + "," + shortest_text(samples.y.step_um));
        grids.push_back(std::to_string(samples.x.count) + "x" + std::to_string(samples.y.count));
        slopes.push_back(shortest_text(samples.max_slope_x) + "," + shortest_text(samples.max_slope_y));
        slices.push_back(setup.slices.nodes_per_unit ? std::to_string(setup.slices.count()) + " at spacing 1/" +
                                                           std::to_string(setup.slices.nodes_per_unit)
                                                     : "1 (xi3 = " + shortest_text(setup.slices.constant_xi3) + ")");
    }

    static std::string join(const std::vector<std::string>& parts) {
        std::string text;
        for (const std::string& part : parts) text += (text.empty() ? "" : ";") + part;
        return text;
    }
};

// Edge truncation on a non-periodic field: w is cut where s leaves the field, so R* holds only
// measured heights, and the lobe loses the cut part of ∫|w|² (its normalisation A_c stays that
// of the whole window; by Parseval the albedo drops by that part). Each sample's w is scaled by
// the part of its cell [s − h/2, s + h/2] inside [0, W] per axis, the midpoint rule of the cut
// integral, so the kept part does not jump with where the grid happens to meet the edge (a
// sample on the edge counts half, not whole: +1.2% of the albedo in tests/lib/lobe/edge_test.cpp
// before). The cut is a step in w whose spectral tails the alias-free step does not provide for:
// a little of their energy folds back into the image (≲ 1% of the albedo there).
void truncate_at_edges(FootprintSamples& samples, const Heightfield& field) {
    const auto inside = [](const SampleAxis& axis, int index, double extent) {
        const double s = axis.first_um + index * axis.step_um, half = 0.5 * axis.step_um;
        return std::clamp((std::min(s + half, extent) - std::max(s - half, 0.0)) / axis.step_um, 0.0, 1.0);
    };
    for (int k = 0; k < samples.y.count; ++k) {
        const double along_y = inside(samples.y, k, field.height_um());
        for (int j = 0; j < samples.x.count; ++j)
            samples.weight[static_cast<std::size_t>(k) * samples.x.count + j] *=
                along_y * inside(samples.x, j, field.width_um());
    }
}

// The part of ∫|w|² ds inside the field: per axis, |w|² = e^{−p²/σ_c²} keeps
// [erf((W − c)/σ_c) + erf(c/σ_c)]/2, and a box of side a keeps its overlap with [0, W] over a.
double energy_inside(const Footprint& footprint, const Heightfield& field) {
    const auto along = [&](double c, double extent, double side) {
        if (footprint.shape == FootprintShape::box) {
            const double half = 0.5 * side;
            return std::max(0.0, std::min(c + half, extent) - std::max(c - half, 0.0)) / side;
        }
        return 0.5 * (std::erf((extent - c) / footprint.sigma_um) + std::erf(c / footprint.sigma_um));
    };
    return along(footprint.centre_um.x, field.width_um(), box_width_um(footprint)) *
           along(footprint.centre_um.y, field.height_um(), box_height_um(footprint));
}

}  // namespace

void scattering_layers(const LobeQuery& query, const ScatteringGeometry& geometry, const ScatteringFactor& factor,
                       LobeImage& image, const ReflectionSource* source) {
    const FftSettings settings = fft_settings(query);
    const FootprintExtent extent = footprint_extent(query.footprint, settings.window_sigmas);
    // ξ3 over the image: 2, or ψ_z = o_z + k·cos θ_o with cos θ_o ∈ (0, 1].
    const bool varying_xi3 = phase_depends_on_outgoing(query.model);
    const double xi3_min = varying_xi3 ? geometry.offset.z : 2.0;
    const double xi3_max = varying_xi3 ? geometry.offset.z + geometry.scale : 2.0;
    const SlopeBound slopes = settings.step_um > 0.0 ? SlopeBound{} : footprint_slopes(*query.surface, extent);

    GridRecord record;
    std::vector<std::string> oversampling;
    bool lowered = false;
    // A smooth source (Gabor's kernels) asks for no oversampling at all (sample_for_wavelength).
    const double wanted = source && source->smooth ? 1.0 : settings.oversampling;
    for (std::size_t layer = 0; layer < image.layers(); ++layer) {
        WavelengthSetup setup;
        setup.query = &query;
        setup.geometry = geometry;
        setup.lambda_um = image.wavelengths_um[layer];
        setup.source = source;
        double q = settings.oversampling;
        setup.samples = sample_for_wavelength(query, geometry, extent, settings, setup.lambda_um, xi3_max, slopes,
                                              source, image_periods(query, geometry, setup.lambda_um), q);
        oversampling.push_back(shortest_text(q));
        lowered = lowered || q < wanted;
        if (settings.truncate_at_edges) truncate_at_edges(setup.samples, *query.field);
        setup.slices = choose_xi3_slices(query.model, setup.samples, setup.lambda_um, xi3_min, xi3_max,
                                         settings.phase_error, kMaxXi3Slices);
        if (setup.slices.nodes_per_unit && !source)
            setup.node_step = phase_factors(setup, 1.0 / setup.slices.nodes_per_unit, false);
        fill_layer(setup, extent, factor, image, layer);
        record.add(setup);
    }
    image.metadata["fft.step_um"] = GridRecord::join(record.steps);
    image.metadata["fft.grid"] = GridRecord::join(record.grids);
    image.metadata["fft.max_slope"] = GridRecord::join(record.slopes);
    image.metadata["fft.xi3_slices"] = GridRecord::join(record.slices);
    image.metadata["fft.half_width_um"] = shortest_text(extent.half_width_um.x);
    if (extent.half_width_um.y != extent.half_width_um.x)
        image.metadata["fft.half_height_um"] = shortest_text(extent.half_width_um.y);
    image.metadata["fft.guard_widths"] = shortest_text(settings.guard_widths);
    image.metadata["fft.oversampling"] = GridRecord::join(oversampling);
    if (lowered)  // the pipeline says it
        image.metadata["note.fft"] = "oversampling lowered from " + shortest_text(wanted) + " to " +
                                     image.metadata["fft.oversampling"] + " to fit the footprint grid in the " +
                                     shortest_text(query.memory_budget_gb) + " GB memory budget (--memory)";
    if (varying_xi3) image.metadata["fft.phase_error"] = shortest_text(settings.phase_error);
    if (settings.truncate_at_edges)
        image.metadata["fft.edge_energy_kept"] =
            shortest_text(std::round(energy_inside(query.footprint, *query.field) * 1e6) / 1e6);
}

FootprintSamples layer_samples(const LobeQuery& query, const ScatteringGeometry& geometry, double lambda_um) {
    const FftSettings settings = fft_settings(query);
    const FootprintExtent extent = footprint_extent(query.footprint, settings.window_sigmas);
    const double xi3_max = phase_depends_on_outgoing(query.model) ? geometry.offset.z + geometry.scale : 2.0;
    const SlopeBound slopes = settings.step_um > 0.0 ? SlopeBound{} : footprint_slopes(*query.surface, extent);
    double q = settings.oversampling;
    FootprintSamples samples =
        sample_for_wavelength(query, geometry, extent, settings, lambda_um, xi3_max, slopes, nullptr,
                              image_periods(query, geometry, lambda_um), q);
    if (settings.truncate_at_edges) truncate_at_edges(samples, *query.field);
    return samples;
}

LobeImage fft_lobe(const LobeQuery& query) {
    // F(λ, cos θ_d) of the material with cos θ_d = ω_i·h = |ψ|/2, the index looked up once per wavelength.
    const bool has_material = !query.material.name.empty();
    std::map<double, ComplexIndex> indices;
    if (has_material)
        for (double lambda : query.wavelengths_um) indices[lambda] = complex_refractive_index(query.material.name, lambda);
    const ScatteringFactor xi1 = [&](const Vec3& psi, const Vec3& omega_o, double lambda) {
        const double fresnel = has_material ? fresnel_conductor(indices.at(lambda), 0.5 * length(psi)) : 1.0;
        return xi1_geometric(query.model, query.omega_i, omega_o) * fresnel;  // Yan 2018 Fig. 6, ξ1·λ²
    };
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    scattering_layers(query, {query.omega_i, 1.0}, xi1, image);
    return image;
}

std::vector<MethodOption> fft_options() {
    return {{"step", "grid step, a length (default: alias-free per wavelength and axis)"},
            {"window", "Gaussian footprint: sampled half-width in sigma_c (default 4)"},
            {"guard", "spectral margin in footprint spectral widths (default 6 for a Gaussian, 32 for a box)"},
            {"oversampling", "step oversampling beyond the alias-free bound, for the C1 interpolant (default 3)"},
            {"phase_error", "GHS, R-GHS, Kirchhoff: xi3 interpolation error bound, in flat-mirror peak amplitudes "
                            "(default 0.01)"},
            {"edge", "non-periodic field: refuse (default) a footprint crossing its border, or truncate the window "
                     "there (the lost energy is recorded as fft.edge_energy_kept)"}};
}

MethodEntry fft_method() {
    return {{"fft",
             "ground truth: R* on a fine grid over the footprint, exact chirp-z transform at every pixel",
             "Yan 2018 eq. 6",
             {Quantity::brdf},
             {},
             fft_options(),
             true},
            fft_lobe,
            nullptr,
            fft_point_field};
}

}  // namespace glintscope
