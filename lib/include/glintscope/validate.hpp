#pragma once
// Validation of one method against another on the same queries: by default the Gabor kernels
// (Yan 2018 §4–5) against the exact FFT ground truth (Yan 2018 eq. 6), over footprints, models,
// kernel densities and wavelengths, with compare_lobes' numbers and the time of each.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "glintscope/compare.hpp"
#include "glintscope/lobe.hpp"

namespace glintscope {

struct ValidationPlan {
    LobeQuery base;                          // heightfield, footprint shape and σ_c, ω_i, λ, ...
    std::string test_method = "gabor";
    std::string reference_method = "fft";
    std::vector<Point2> centres;             // footprint centres (footprint_centres)
    std::vector<DiffractionModel> models;    // default: the base query's model
    std::vector<int> kernels_per_texel;      // the test method's option; empty: its default
};

struct ValidationRow {
    Point2 centre_um;
    DiffractionModel model = DiffractionModel::rohs;
    int kernels_per_texel = 0;               // 0: the test method's default
    LayerComparison comparison;              // one wavelength
    double test_seconds = 0.0;               // for the whole query (all wavelengths)
    double reference_seconds = 0.0;
};

// `count` footprint centres spread over the field: a grid of ⌈√count⌉² cells' centres when
// `grid`, else seeded uniform positions; kept 3.25σ_c (or half a box) from the edges where the
// field is large enough, so that a non-periodic scan is not read across its seam.
std::vector<Point2> footprint_centres(const Heightfield& field, const Footprint& footprint, int count, bool grid,
                                      unsigned seed = 1);

// Progress: called after each computed lobe with (done, total, what was computed).
using ProgressCallback = std::function<void(std::size_t done, std::size_t total, const std::string& what)>;

// Called with each compared pair (for pictures); `row` is the pair's first row.
using PairCallback = std::function<void(const ValidationRow& row, const LobeImage& test, const LobeImage& reference)>;

// Every combination of centre × model × density, one row per wavelength. The reference lobe of a
// (centre, model) is computed once and shared by the densities.
std::vector<ValidationRow> run_validation(const ValidationPlan& plan, const ProgressCallback& progress = {},
                                          const PairCallback& pair = {});

// test − reference, per pixel and layer (a signed image: figure.hpp draws it on a diverging scale).
LobeImage difference_image(const LobeImage& test, const LobeImage& reference);

// Convergence of the two methods at the plan's first centre, model and wavelength:
// - Gabor against the FFT ground truth as the kernels per texel K go 1, 2, 3, 4;
// - the FFT against itself at a quarter of its automatic step, as the step goes from twice the
//   automatic one down to half of it (what the automatic choice leaves on the table).
struct ConvergencePoint {
    std::string series;    // "gabor_kernels_per_texel" or "fft_step_um"
    double parameter = 0.0;
    double relative_l2 = 0.0;
};
std::vector<ConvergencePoint> run_convergence(const ValidationPlan& plan, const ProgressCallback& progress = {});
std::string convergence_csv(const std::vector<ConvergencePoint>& points);

// The rows as CSV (one header line, then one line per row) and as a JSON report (the plan's
// base query keys, then the rows; numbers as JSON numbers).
std::string validation_csv(const std::vector<ValidationRow>& rows);
std::string validation_json(const ValidationPlan& plan, const std::vector<ValidationRow>& rows);

}  // namespace glintscope
