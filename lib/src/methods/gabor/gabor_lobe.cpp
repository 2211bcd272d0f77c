// Whole Gabor lobe images (Yan 2018 §4–5) on the projected-disk grid of outgoing directions.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "gabor_kernels.hpp"
#include "gabor_product.hpp"
#include "gabor.hpp"
#include "glintscope/parallel.hpp"

namespace glintscope {
namespace {

using gabor::KernelArrays;
using gabor::KernelGrid;

constexpr double kPi = std::numbers::pi;
constexpr int kBlockKernels = 8;                     // footprint kernels per block side (per-pixel pruning)
constexpr double kPanelTableBytes = 256.0 * (1 << 20);  // transform tables of one panel of the image

std::string format_number(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.10g", value);
    return buffer;
}

// ---- The footprint's kernels -----------------------------------------------------------------

// The kernels inside the coherence window, block by block (kBlockKernels² cells of the kernel
// grid), each block with the range of H' over its kernels for directional pruning.
struct FootprintKernels {
    struct Block {
        std::size_t begin = 0;
        std::size_t end = 0;
        double x_min = 0.0;
        double x_max = 0.0;
        double y_min = 0.0;
        double y_max = 0.0;
    };
    KernelArrays arrays;
    std::vector<Block> blocks;
};

// Kernel indices i with centre (i + ½) l in [centre − extent, centre + extent].
void index_range(double centre, double extent, double spacing, long long& first, long long& last) {
    first = static_cast<long long>(std::ceil((centre - extent) / spacing - 0.5));
    last = static_cast<long long>(std::floor((centre + extent) / spacing - 0.5));
}

FootprintKernels gather_kernels(const BicubicInterpolant& surface, const KernelGrid& grid,
                                const gabor::CoherenceWindow& window, Point2 centre) {
    window.check_kernel_count(grid);
    long long i0, i1, j0, j1;
    index_range(centre.x, window.half_extent_um(), grid.spacing_um, i0, i1);
    index_range(centre.y, window.half_extent_um(), grid.spacing_um, j0, j1);
    const double reference_height = surface.height(centre.x, centre.y);
    const double weight_scale = grid.spacing_um * grid.spacing_um;
    FootprintKernels kernels;
    std::vector<SurfacePoint> row(kBlockKernels);
    for (long long bj = j0; bj <= j1; bj += kBlockKernels)
        for (long long bi = i0; bi <= i1; bi += kBlockKernels) {
            FootprintKernels::Block block{kernels.arrays.size(), 0, 1e300, -1e300, 1e300, -1e300};
            for (long long j = bj; j <= std::min(j1, bj + kBlockKernels - 1); ++j) {
                const double py = grid.centre(j) - centre.y;
                long long first = 0;
                long long last = -1;
                if (!window.row_span(grid, centre.x, py, bi, std::min(i1, bi + kBlockKernels - 1), first, last))
                    continue;
                const int count = static_cast<int>(last - first + 1);
                gabor::evaluate_kernels(surface, grid, first, j, count, 1, row.data());
                kernels.arrays.reserve_more(count);
                for (int k = 0; k < count; ++k) {
                    const double px = grid.centre(first + k) - centre.x;
                    const SurfacePoint& p = row[k];
                    kernels.arrays.push(px, py, p, reference_height, window.weight(px, py) * weight_scale);
                    block.x_min = std::min(block.x_min, p.dh_dx);
                    block.x_max = std::max(block.x_max, p.dh_dx);
                    block.y_min = std::min(block.y_min, p.dh_dy);
                    block.y_max = std::max(block.y_max, p.dh_dy);
                }
            }
            block.end = kernels.arrays.size();
            if (block.end > block.begin) kernels.blocks.push_back(block);
        }
    return kernels;
}

// ---- The sample grid -------------------------------------------------------------------------

// M = N·S samples per axis: sample m lies in pixel m / S at sub-pixel offset (m mod S + ½)/S − ½,
// so the samples of all pixels form one regular grid on the disk (the FFT lobe's sub-pixels).
struct SampleGrid {
    int resolution = 0;
    int supersample = 1;

    int size() const { return resolution * supersample; }
    DiskPoint point(int row, int col) const {
        return disk_subpixel_point(row / supersample, col / supersample, row % supersample, col % supersample,
                                   resolution, supersample);
    }
    double x(int col) const { return point(0, col).x; }
    double y(int row) const { return point(row, 0).y; }
    bool inside_disk(int row, int col) const { return inside_unit_disk(point(row, col)); }
};

struct LayerSetup {
    const LobeQuery& query;
    const KernelGrid& grid;
    double area_um2;
    double lambda_um;
    gabor::FresnelAtWavelength fresnel;
    SampleGrid samples;
};

gabor::TransformPoint transform_at(const LayerSetup& layer, DiskPoint p) {
    return gabor::transform_point(layer.query.model, layer.fresnel, layer.query.omega_i, direction_from_disk(p.x, p.y),
                                  layer.lambda_um, layer.area_um2);
}

// ---- GHS, R-GHS, Kirchhoff: sample by sample over pruned kernel blocks ----------------------

void per_sample_layer(const LayerSetup& layer, const FootprintKernels& kernels, std::vector<double>& sums) {
    const SampleGrid& samples = layer.samples;
    const int m = samples.size();
    parallel_for(m, 1, [&](std::size_t begin, std::size_t end) {
        for (int row = static_cast<int>(begin); row < static_cast<int>(end); ++row)
            for (int col = 0; col < m; ++col) {
                const DiskPoint p = samples.point(row, col);
                if (!inside_unit_disk(p)) continue;
                const gabor::TransformPoint point = transform_at(layer, p);
                std::complex<double> field = 0.0;
                for (const FootprintKernels::Block& block : kernels.blocks)
                    if (gabor::slopes_reach(point.vx, point.vy, point.xi3_over_lambda, layer.grid.reach, block.x_min,
                                            block.x_max, block.y_min, block.y_max))
                        field += gabor::sum_transforms(kernels.arrays, block.begin, block.end, point, layer.grid);
                sums[static_cast<std::size_t>(row) * m + col] = point.brdf_scale * std::norm(field);  // eq. 16–17
            }
    });
}

// ---- OHS, R-OHS: banded complex matrix product ------------------------------------------------

// Samples along one image axis: the disk coordinate of sample m and the ω_i component added to it.
struct AxisSamples {
    const SampleGrid& samples;
    bool along_y;
    double omega_i_component;

    double coordinate(int m) const { return along_y ? samples.y(m) : samples.x(m); }
    double step() const { return (along_y ? -2.0 : 2.0) / samples.size(); }  // d coordinate / dm
};

// One axis of every kernel's separable transform over a panel's samples [first_sample,
// first_sample + count), in the tile blocks of gabor_product.hpp (B blocks along x, A blocks
// along y): block b of kernel k at values[(b·kernels + k)·floats_per_block]. Kernel k is
// nonzero only on its band [band_first[k], band_first[k] + band_count[k]), where |v + a_k| ≤ reach.
struct AxisTable {
    bool along_y = false;
    int first_sample = 0;
    int count = 0;
    std::size_t kernels = 0;
    std::vector<int> band_first;
    std::vector<int> band_count;
    std::vector<float> values;  // grows only: tables are refilled for every panel and wavelength

    int samples_per_block() const { return along_y ? gabor::kTileRows : gabor::kTileCols; }
    int floats_per_block() const { return along_y ? gabor::kRowBlockFloats : gabor::kColBlockFloats; }
    int blocks() const { return (count + samples_per_block() - 1) / samples_per_block(); }
    const float* block(std::size_t k, int b) const {
        return values.data() + (static_cast<std::size_t>(b) * kernels + k) * floats_per_block();
    }
    bool band_meets(std::size_t k, int first, int n) const {
        return band_count[k] > 0 && band_first[k] < first + n && band_first[k] + band_count[k] > first;
    }
};

// The band of kernel k along one axis: the samples with |(ω_i + coordinate)/λ + a| ≤ reach, found
// from the affine sample coordinates and then confirmed with the exact test.
void find_band(const AxisSamples& axis, double lambda, double reach, double a, int first_sample, int count,
               int& band_first, int& band_count) {
    const auto inside = [&](int m) {
        const double u = (axis.omega_i_component + axis.coordinate(m)) / lambda + a;
        return u * u <= reach * reach;
    };
    const double c0 = axis.coordinate(0);
    const double lo = (lambda * (-a - reach) - axis.omega_i_component - c0) / axis.step();
    const double hi = (lambda * (-a + reach) - axis.omega_i_component - c0) / axis.step();
    const int last_sample = first_sample + count - 1;
    const auto clamp_index = [&](double m) {
        return static_cast<int>(std::clamp(m, double(first_sample), double(last_sample)));
    };
    int first = clamp_index(std::ceil(std::min(lo, hi)));
    int last = clamp_index(std::floor(std::max(lo, hi)));
    while (first > first_sample && inside(first - 1)) --first;
    while (first <= last && !inside(first)) ++first;
    while (last < last_sample && last >= first && inside(last + 1)) ++last;
    while (last >= first && !inside(last)) --last;
    band_first = first;
    band_count = std::max(0, last - first + 1);
}

// Writes kernel k's factor along the axis, X(v) = factor · e^{−i2π p v} e^{−β(v + a)²} at
// v = (ω_i + coordinate(m))/λ on its band and 0 elsewhere. Along the regular samples successive
// values differ by a ratio that itself changes by the constant factor e^{−2β Δv²}, so the band
// costs two complex multiplications per sample.
void fill_axis(const AxisSamples& axis, double lambda, const KernelGrid& grid, double p, double a,
               std::complex<double> factor, std::size_t k, AxisTable& table) {
    const int per_block = table.samples_per_block();
    for (int b = 0; b < table.blocks(); ++b) {
        float* block =
            table.values.data() + (static_cast<std::size_t>(b) * table.kernels + k) * table.floats_per_block();
        std::fill(block, block + table.floats_per_block(), 0.0f);
    }
    const int first = table.band_first[k];
    const int count = table.band_count[k];
    if (count == 0) return;
    const double v = (axis.omega_i_component + axis.coordinate(first)) / lambda;
    const double u = v + a;
    const double dv = axis.step() / lambda;
    const double turns = p * v - std::nearbyint(p * v);
    const std::complex<double> start = factor * std::exp(-grid.beta * u * u) *
                                       std::complex<double>(std::cos(2 * kPi * turns), -std::sin(2 * kPi * turns));
    double re = start.real();
    double im = start.imag();
    const double ratio_scale = std::exp(-grid.beta * (2.0 * u * dv + dv * dv));
    double ratio_re = ratio_scale * std::cos(2 * kPi * p * dv);
    double ratio_im = -ratio_scale * std::sin(2 * kPi * p * dv);
    const double ratio_change = std::exp(-2.0 * grid.beta * dv * dv);
    for (int m = first; m < first + count; ++m) {
        const int i = m - table.first_sample;
        float* block = table.values.data() +
                       (static_cast<std::size_t>(i / per_block) * table.kernels + k) * table.floats_per_block();
        const int at = 2 * (i % per_block);
        block[at] = static_cast<float>(re);
        block[at + 1] = static_cast<float>(im);
        const double next_re = re * ratio_re - im * ratio_im;
        im = re * ratio_im + im * ratio_re;
        re = next_re;
        ratio_re *= ratio_change;
        ratio_im *= ratio_change;
    }
}

// Fills the table for the n = a.size() kernels with positions p (along the axis), a_k and factors.
void fill_axis_table(const AxisSamples& axis, double lambda, const KernelGrid& grid, const std::vector<double>& p,
                     const std::vector<double>& a, const std::vector<std::complex<double>>& factors, int first_sample,
                     int count, AxisTable& table) {
    table.along_y = axis.along_y;
    table.first_sample = first_sample;
    table.count = count;
    table.kernels = a.size();
    table.band_first.resize(table.kernels);
    table.band_count.resize(table.kernels);
    const std::size_t floats = static_cast<std::size_t>(table.blocks()) * table.kernels * table.floats_per_block();
    if (table.values.size() < floats) table.values.resize(floats);
    parallel_for(table.kernels, 256, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            find_band(axis, lambda, grid.reach, a[k], first_sample, count, table.band_first[k], table.band_count[k]);
            fill_axis(axis, lambda, grid, p[k], a[k], factors[k], k, table);
        }
    });
}

// U over one tile of samples (kTileRows × kTileCols at row0, col0, clipped to the panel's tables),
// then f_r = ξ1/A_c |U|² at the samples inside the disk.
void product_tile(const LayerSetup& layer, const AxisTable& along_x, const AxisTable& along_y, int row0, int col0,
                  std::vector<double>& sums) {
    const SampleGrid& samples = layer.samples;
    const int rows = std::min(gabor::kTileRows, along_y.first_sample + along_y.count - row0);
    const int cols = std::min(gabor::kTileCols, along_x.first_sample + along_x.count - col0);
    // Tiles wholly outside the unit disk stay 0.
    const double x_near = std::clamp(0.0, samples.x(col0), samples.x(col0 + cols - 1));
    const double y_near = std::clamp(0.0, samples.y(row0 + rows - 1), samples.y(row0));
    if (x_near * x_near + y_near * y_near >= 1.0) return;

    const int row_block = (row0 - along_y.first_sample) / gabor::kTileRows;
    const int col_block = (col0 - along_x.first_sample) / gabor::kTileCols;
    std::vector<const float*> a_blocks;
    std::vector<const float*> b_blocks;
    for (std::size_t k = 0; k < along_x.kernels; ++k)
        if (along_x.band_meets(k, col0, cols) && along_y.band_meets(k, row0, rows)) {
            a_blocks.push_back(along_y.block(k, row_block));
            b_blocks.push_back(along_x.block(k, col_block));
        }
    // Register blocks with a sample inside the disk (and the panel).
    bool wanted[gabor::kBlocksPerTile] = {};
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c)
            if (samples.inside_disk(row0 + r, col0 + c))
                wanted[(r / gabor::kBlockRows) * (gabor::kTileCols / gabor::kBlockCols) + c / gabor::kBlockCols] = true;
    std::vector<double> u_re(gabor::kTileRows * gabor::kTileCols, 0.0);
    std::vector<double> u_im(u_re.size(), 0.0);
    gabor::accumulate_tile(a_blocks.data(), b_blocks.data(), static_cast<int>(a_blocks.size()), wanted, u_re.data(),
                           u_im.data());
    const int m = samples.size();
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            const DiskPoint p = samples.point(row0 + r, col0 + c);
            if (!inside_unit_disk(p)) continue;
            const std::size_t i = static_cast<std::size_t>(r) * gabor::kTileCols + c;
            const double intensity = u_re[i] * u_re[i] + u_im[i] * u_im[i];
            sums[static_cast<std::size_t>(row0 + r) * m + col0 + c] = transform_at(layer, p).brdf_scale * intensity;
        }
}

struct ProductTables {
    AxisTable along_x;
    AxisTable along_y;
};

void product_layer(const LayerSetup& layer, const FootprintKernels& kernels, ProductTables& tables,
                   std::vector<double>& sums) {
    const KernelArrays& k = kernels.arrays;
    const std::size_t n = k.size();
    const Vec3 wi = layer.query.omega_i;
    // ξ3 = 2 and ξ2 = 1 for OHS and R-OHS (Fig. 6), whatever ω_o.
    const double xi3_over_lambda = xi3(layer.query.model, wi, wi) / layer.lambda_um;
    std::vector<double> a_x(n), a_y(n);
    std::vector<std::complex<double>> ones(n, 1.0), coefficients(n);
    for (std::size_t i = 0; i < n; ++i) {
        a_x[i] = xi3_over_lambda * k.slope_x[i];  // eq. 15
        a_y[i] = xi3_over_lambda * k.slope_y[i];
        const double turns = xi3_over_lambda * k.height[i];
        coefficients[i] = k.weight[i] * std::complex<double>(std::cos(2 * kPi * turns), -std::sin(2 * kPi * turns));
    }
    const SampleGrid& samples = layer.samples;
    const AxisSamples x_axis{samples, false, wi.x};
    const AxisSamples y_axis{samples, true, wi.y};
    // Panels of samples bound the table memory (8 bytes per kernel and sample on each axis); they
    // hold whole tiles and whole pixels.
    const int unit = std::lcm(gabor::kTileCols, samples.supersample);
    const double panel_target = kPanelTableBytes / (16.0 * static_cast<double>(std::max<std::size_t>(n, 1)));
    const int m = samples.size();
    const int panel_size = unit * std::clamp(static_cast<int>(panel_target / unit), 1, m / unit + 1);
    for (int row0 = 0; row0 < m; row0 += panel_size)
        for (int col0 = 0; col0 < m; col0 += panel_size) {
            const int rows = std::min(panel_size, m - row0);
            const int cols = std::min(panel_size, m - col0);
            const AxisTable& along_x = tables.along_x;
            const AxisTable& along_y = tables.along_y;
            fill_axis_table(x_axis, layer.lambda_um, layer.grid, k.px, a_x, ones, col0, cols, tables.along_x);
            fill_axis_table(y_axis, layer.lambda_um, layer.grid, k.py, a_y, coefficients, row0, rows, tables.along_y);
            const int tile_rows = along_y.blocks();
            const int tile_cols = along_x.blocks();
            parallel_for(static_cast<std::size_t>(tile_rows) * tile_cols, 1, [&](std::size_t begin, std::size_t end) {
                for (std::size_t t = begin; t < end; ++t)
                    product_tile(layer, along_x, along_y, row0 + static_cast<int>(t / tile_cols) * gabor::kTileRows,
                                 col0 + static_cast<int>(t % tile_cols) * gabor::kTileCols, sums);
            });
        }
}

}  // namespace

LobeImage gabor_lobe(const LobeQuery& query) {
    const GaborSettings settings = gabor_settings(query);
    const BicubicInterpolant& surface = *query.surface;
    const KernelGrid grid = gabor::kernel_grid(surface.texel_um(), settings);
    const gabor::CoherenceWindow window(query.footprint, settings.footprint_sigmas);
    const FootprintKernels kernels = gather_kernels(surface, grid, window, query.footprint.centre_um);
    const bool per_sample = phase_depends_on_outgoing(query.model);

    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    const SampleGrid samples{query.resolution, query.supersample};
    const int m = samples.size();
    std::vector<double> sums(static_cast<std::size_t>(m) * m);
    std::vector<double> pixel_sums(static_cast<std::size_t>(query.resolution) * query.resolution);
    ProductTables tables;
    for (std::size_t layer = 0; layer < query.wavelengths_um.size(); ++layer) {
        const double lambda = query.wavelengths_um[layer];
        const gabor::FresnelAtWavelength fresnel(query.material, lambda);
        const LayerSetup setup{query, grid, window.area_um2(), lambda, fresnel, samples};
        std::fill(sums.begin(), sums.end(), 0.0);
        if (per_sample)
            per_sample_layer(setup, kernels, sums);
        else
            product_layer(setup, kernels, tables, sums);
        // Each pixel averages its S×S samples (samples outside the disk count as 0).
        const int s = samples.supersample;
        for (int r = 0; r < query.resolution; ++r)
            for (int c = 0; c < query.resolution; ++c) {
                double total = 0.0;
                for (int b = 0; b < s; ++b)
                    for (int a = 0; a < s; ++a) total += sums[static_cast<std::size_t>(r * s + b) * m + c * s + a];
                pixel_sums[static_cast<std::size_t>(r) * query.resolution + c] = total;
            }
        store_subpixel_means(image, layer, pixel_sums, s);
    }

    image.metadata["gabor.kernels_per_texel"] = std::to_string(settings.kernels_per_texel);
    image.metadata["gabor.kernel_spacing_um"] = format_number(grid.spacing_um);
    image.metadata["gabor.kernel_sigma_um"] = format_number(grid.sigma_um);
    image.metadata["gabor.kernels"] = std::to_string(kernels.arrays.size());
    if (query.footprint.shape == FootprintShape::gaussian)
        image.metadata["gabor.footprint_truncation_sigmas"] = format_number(settings.footprint_sigmas);
    image.metadata["gabor.kernel_truncation_sigmas"] = format_number(settings.kernel_sigmas);
    image.metadata["gabor.evaluation"] =
        per_sample ? "per sample over pruned kernel blocks" : "banded separable matrix product";
    return image;
}

MethodEntry gabor_method() {
    return {{"gabor",
             "Gabor kernels, one per cell of a regular grid, summed in closed form (default K = 2 per texel)",
             "Yan 2018 §4-5, eq. 16-17",
             {Quantity::brdf},
             {},
             {{"kernels_per_texel", "kernels per texel side K, an integer 1-16 (default 2)"},
              {"footprint_truncation", "drop kernels beyond this many sigma_c from the centre (default 3.25)"},
              {"kernel_truncation", "cut each kernel's transform at this many of its sigmas (default 3)"}},
             true},
            gabor_lobe};
}

}  // namespace glintscope
