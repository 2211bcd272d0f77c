#pragma once
// Validation of one method against another on the same queries: by default the Gabor kernels
// (Yan 2018 §4–5) against the exact FFT ground truth (Yan 2018 eq. 6), over footprints, models,
// kernel densities and wavelengths, with compare_lobes' numbers and the time of each.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "glintscope/lobe/compare.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/output/plot.hpp"

namespace glintscope {

struct ValidationPlan {
    LobeQuery base;                          // heightfield, footprint(s), ω_i, λ, ...: a row per footprint
    std::string test_method = "gabor";
    std::string reference_method = "fft";
    std::vector<DiffractionModel> models;    // default: validation_models
    std::vector<int> kernels_per_texel;      // the test method's option; empty: its default
    std::vector<int> orders;                 // the test method's option "order" (gabor: 1, 2); empty: its default
};

struct ValidationRow {
    Point2 centre_um;
    DiffractionModel model = DiffractionModel::rohs;
    int kernels_per_texel = 0;               // 0: the test method's default
    int order = 0;                           // 0: the test method's default
    LayerComparison comparison;              // one wavelength
    double test_seconds = 0.0;               // for the whole query (all wavelengths)
    double reference_seconds = 0.0;
};

// The models a plan runs: its own, or by default the base query's model, except when exactly one
// of the two methods ignores the diffraction model (geometric optics against a wave method):
// then Kirchhoff, the model whose λ → 0 limit is geometric optics (docs/validation.md).
std::vector<DiffractionModel> validation_models(const ValidationPlan& plan);

// What the library chose for a plan that its caller should say once (e.g. the Kirchhoff default).
std::vector<std::string> validation_notes(const ValidationPlan& plan);

// Progress: called after each computed lobe with (done, total, what was computed).
using ProgressCallback = std::function<void(std::size_t done, std::size_t total, const std::string& what)>;

// Called with each compared pair (for pictures); `row` is the pair's first row.
using PairCallback = std::function<void(const ValidationRow& row, const LobeImage& test, const LobeImage& reference)>;

// Every combination of footprint (base.footprints, each on its own) × model × density × order, one
// row per wavelength. The reference lobe of a (centre, model) is computed once and shared by the
// densities; test and reference share the reference method's supersampling.
std::vector<ValidationRow> run_validation(const ValidationPlan& plan, const ProgressCallback& progress = {},
                                          const PairCallback& pair = {});

// Convergence of the two methods at the plan's first centre, model and wavelength:
// - Gabor against the FFT ground truth as the kernels per texel K go 1, 2, 3, 4, at both orders;
// - the FFT against itself at a quarter of its automatic step, as the step goes from twice the
//   automatic one down to half of it (what the automatic choice leaves on the table).
struct ConvergencePoint {
    std::string series;    // "gabor_order_1_kernels_per_texel", "gabor_order_2_kernels_per_texel" or "fft_step_um"
    double parameter = 0.0;
    double relative_l2 = 0.0;
};
std::vector<ConvergencePoint> run_convergence(const ValidationPlan& plan, const ProgressCallback& progress = {});
std::string convergence_csv(const std::vector<ConvergencePoint>& points);

// The verdict over footprints: per model × K × order × wavelength, the mean and the worst relative L2 and
// peak error over the footprints, and the mean energy ratio (test albedo / reference albedo),
// in order of first appearance in the rows.
struct ValidationSummary {
    DiffractionModel model = DiffractionModel::rohs;
    int kernels_per_texel = 0;
    int order = 0;
    double wavelength_um = 0.0;
    std::size_t footprints = 0;
    double mean_relative_l2 = 0.0;
    double worst_relative_l2 = 0.0;
    double mean_peak_error = 0.0;
    double worst_peak_error = 0.0;
    double mean_smoothed_l2 = 0.0;           // LayerComparison::smoothed_relative_l2, speckle-free
    double worst_smoothed_l2 = 0.0;
    double mean_energy_ratio = 0.0;
};
std::vector<ValidationSummary> summarize_validation(const std::vector<ValidationRow>& rows);

// validate's summary figure: the mean relative L2 (in %) against K, one series per model (and
// order, when several ran), each point the mean over the wavelengths of the summary's mean over
// the footprints at that K; the caption says so.
Plot error_against_k_plot(const ValidationPlan& plan, const std::vector<ValidationSummary>& summary);

// What every column means, one line each ("name: meaning"), for --help, the report and docs.
const std::vector<std::string>& validation_column_definitions();

// The rows as CSV (one header line, then one line per row), the summary as CSV, and a JSON report
// that describes itself: format, version, command line, methods, the base query keys, every model,
// K, footprint centre and wavelength run, the column definitions, the summary, then the rows (each
// with its picture's file name when `pictures` names one per row's pair: pair-N.png).
std::string validation_csv(const std::vector<ValidationRow>& rows);
std::string validation_summary_csv(const std::vector<ValidationSummary>& summary);
std::string validation_json(const ValidationPlan& plan, const std::vector<ValidationRow>& rows,
                            const std::string& command_line = "", const std::vector<std::string>& pictures = {});

}  // namespace glintscope
