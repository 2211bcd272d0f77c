// Whole Gabor lobe images (Yan 2018 §4–5) on the projected-disk grid of outgoing directions.
#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "gabor_field.hpp"
#include "gabor_kernels.hpp"
#include "gabor_product.hpp"
#include "gabor.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "wave/xi3_slices.hpp"

namespace glintscope {
namespace {

using gabor::KernelArrays;
using gabor::KernelGrid;

constexpr double kPanelTableBytes = 256.0 * (1 << 20);  // transform tables of one panel of the image
constexpr int kMaxXi3Nodes = 512;

// Yan 2018 eq. 16 weights each kernel by the window at its centre, so the kernels sum to the
// Gaussian window blurred by G(σ_k), whose energy is f = Π_axes √(σ²/(σ² + σ_k²)) of the window's
// (σ_c²/(σ_c² + σ_k²) when round): a flat mirror's albedo is exactly f of the FFT's, a rough
// surface's within 0.15% of it for σ_c ≥ 1.4 σ_k (docs/gabor.md "Flat mirror"). 1 for a box.
double kernel_blur_factor(const Footprint& footprint, const KernelGrid& grid) {
    if (footprint.shape != FootprintShape::gaussian) return 1.0;
    const auto axis = [&](double sigma) { return sigma / std::sqrt(sigma * sigma + grid.sigma_um * grid.sigma_um); };
    return axis(footprint.sigma_um) * axis(minor_sigma_um(footprint));
}

// What brings the blur factor to 0.99: kernels_per_texel K ≤ 16 with σ_k ≤ σ/√99 on the narrower
// axis, else the fft method.
std::string remedy(const Footprint& footprint, const KernelGrid& grid) {
    const double texel = grid.spacing_um * grid.kernels_per_texel;
    const int needed = static_cast<int>(std::ceil(texel * std::sqrt(99.0) / (2.0 * minor_sigma_um(footprint))));
    return needed <= 16 ? "kernels_per_texel " + std::to_string(needed) + " brings f to 0.99"
                        : "use the fft method (kernels_per_texel would need " + std::to_string(needed) + ")";
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
    double phase_error;  // ξ3 interpolation bound (xi3_slices.hpp)
};

gabor::TransformPoint transform_at(const LayerSetup& layer, DiskPoint p) {
    return gabor::transform_point(layer.query.model, layer.fresnel, layer.query.omega_i, direction_from_disk(p.x, p.y),
                                  layer.lambda_um, layer.area_um2);
}

// ---- Banded complex matrix products, one per ξ3 node ------------------------------------------

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
                                       std::complex<double>(std::cos(2 * pi * turns), -std::sin(2 * pi * turns));
    double re = start.real();
    double im = start.imag();
    const double ratio_scale = std::exp(-grid.beta * (2.0 * u * dv + dv * dv));
    double ratio_re = ratio_scale * std::cos(2 * pi * p * dv);
    double ratio_im = -ratio_scale * std::sin(2 * pi * p * dv);
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

// The ξ3 of every sample and the ξ3 nodes whose products it needs (Xi3Slices, as the FFT method:
// R̃* is linear in R*, and each kernel's term is smooth in ξ3, so a sample interpolates the
// products of its four nearest nodes with Lagrange weights).
struct NodePlan {
    Xi3Slices slices;
    std::vector<double> xi3_at;  // per sample (0 outside the disk)
};

// Whether the sample at index i (inside the disk) gives `node` a non-zero weight.
bool sample_needs_node(const NodePlan& plan, int node, std::size_t i) {
    if (!plan.slices.nodes_per_unit) return true;
    const double xi3 = plan.xi3_at[i];
    return plan.slices.lowest_node(xi3) <= node && node <= plan.slices.highest_node(xi3);
}

// U_c = Σ_k coefficient_c,k X_k(v_x) Y_k(v_y) over one tile of samples (kTileRows × kTileCols at
// row0, col0, clipped to the panel's tables), written into u (one complex image per component),
// computed only in the register blocks that hold a sample inside the disk which needs the node.
void product_tile(const SampleGrid& samples, const NodePlan& plan, int node, const AxisTable& along_x,
                  const std::vector<AxisTable>& along_y, int row0, int col0,
                  std::vector<std::vector<std::complex<double>>>& u) {
    const int rows = std::min(gabor::kTileRows, along_y[0].first_sample + along_y[0].count - row0);
    const int cols = std::min(gabor::kTileCols, along_x.first_sample + along_x.count - col0);
    const int row_block = (row0 - along_y[0].first_sample) / gabor::kTileRows;
    const int col_block = (col0 - along_x.first_sample) / gabor::kTileCols;
    // Register blocks with a sample inside the disk (and the panel).
    const int m = samples.size();
    bool wanted[gabor::kBlocksPerTile] = {};
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c)
            if (samples.inside_disk(row0 + r, col0 + c) &&
                sample_needs_node(plan, node, static_cast<std::size_t>(row0 + r) * m + col0 + c))
                wanted[(r / gabor::kBlockRows) * (gabor::kTileCols / gabor::kBlockCols) + c / gabor::kBlockCols] = true;
    std::vector<double> u_re(gabor::kTileRows * gabor::kTileCols), u_im(u_re.size());
    std::vector<const float*> a_blocks, b_blocks;
    for (std::size_t component = 0; component < along_y.size(); ++component) {
        a_blocks.clear();
        b_blocks.clear();
        for (std::size_t k = 0; k < along_x.kernels; ++k)
            if (along_x.band_meets(k, col0, cols) && along_y[component].band_meets(k, row0, rows)) {
                a_blocks.push_back(along_y[component].block(k, row_block));
                b_blocks.push_back(along_x.block(k, col_block));
            }
        std::fill(u_re.begin(), u_re.end(), 0.0);
        std::fill(u_im.begin(), u_im.end(), 0.0);
        gabor::accumulate_tile(a_blocks.data(), b_blocks.data(), static_cast<int>(a_blocks.size()), wanted,
                               u_re.data(), u_im.data());
        for (int r = 0; r < rows; ++r)
            for (int c = 0; c < cols; ++c) {
                const std::size_t t = static_cast<std::size_t>(r) * gabor::kTileCols + c;
                u[component][static_cast<std::size_t>(row0 + r) * m + col0 + c] = {u_re[t], u_im[t]};
            }
    }
}

// Whether a tile has a sample inside the disk whose ξ3 gives `node` a weight. ξ3 = ψ_z grows
// as the sample nears the disk centre, so the tile's range is that of its nearest and farthest
// points from it.
bool tile_needs_node(const LayerSetup& layer, const NodePlan& plan, int node, int row0, int col0, int rows, int cols) {
    const SampleGrid& samples = layer.samples;
    const double x0 = samples.x(col0), x1 = samples.x(col0 + cols - 1);
    const double y0 = samples.y(row0 + rows - 1), y1 = samples.y(row0);
    const double near_x = std::clamp(0.0, x0, x1), near_y = std::clamp(0.0, y0, y1);
    if (near_x * near_x + near_y * near_y >= 1.0) return false;  // wholly outside the disk
    if (!plan.slices.nodes_per_unit) return true;
    const double far_x = std::max(std::abs(x0), std::abs(x1)), far_y = std::max(std::abs(y0), std::abs(y1));
    const double far2 = std::min(1.0, far_x * far_x + far_y * far_y);
    const double wz = layer.query.omega_i.z;
    const double xi3_high = wz + std::sqrt(1.0 - (near_x * near_x + near_y * near_y));  // Yan 2018 Fig. 6: ψ·n
    const double xi3_low = wz + std::sqrt(1.0 - far2);
    return plan.slices.lowest_node(xi3_low) <= node && node <= plan.slices.highest_node(xi3_high);
}

struct ProductTables {
    AxisTable along_x;
    std::vector<AxisTable> along_y;  // one per component: U, and for Kirchhoff U_x and U_y
};

// Adds to `field` the node's U (Kirchhoff: U − (g_x U_x + g_y U_y), ξ2 = 1 − g·H' being affine in
// H', Yan 2018 Fig. 6) at every sample of the tiles that need it, times its interpolation weight.
void add_node(const LayerSetup& layer, const gabor::FootprintKernels& kernels, const NodePlan& plan, int node,
              double mean_height, ProductTables& tables, std::vector<std::vector<std::complex<double>>>& u,
              std::vector<std::complex<double>>& field) {
    const KernelArrays& k = kernels.arrays;
    const std::size_t n = k.size();
    const double xi3_over_lambda = plan.slices.node(node) / layer.lambda_um;
    const std::size_t components = u.size();
    std::vector<double> a_x(n), a_y(n);
    std::vector<std::complex<double>> ones(n, 1.0);
    std::vector<std::vector<std::complex<double>>> coefficients(components, std::vector<std::complex<double>>(n));
    for (std::size_t i = 0; i < n; ++i) {
        a_x[i] = xi3_over_lambda * k.slope_x[i];  // Yan 2018 eq. 15
        a_y[i] = xi3_over_lambda * k.slope_y[i];
        const double turns = xi3_over_lambda * (k.height[i] - mean_height);
        const std::complex<double> c = k.weight[i] * std::complex<double>(std::cos(2 * pi * turns), -std::sin(2 * pi * turns));
        coefficients[0][i] = c;  // Yan 2018 eq. 14
        if (components == 3) {
            coefficients[1][i] = c * k.slope_x[i];
            coefficients[2][i] = c * k.slope_y[i];
        }
    }
    const SampleGrid& samples = layer.samples;
    const Vec3 wi = layer.query.omega_i;
    const AxisSamples x_axis{samples, false, wi.x};
    const AxisSamples y_axis{samples, true, wi.y};
    // Panels of samples bound the table memory (8 bytes per kernel and sample on each axis); they
    // hold whole tiles and whole pixels.
    const int unit = std::lcm(gabor::kTileCols, samples.supersample);
    const double panel_target =
        kPanelTableBytes / (8.0 * double(components + 1) * static_cast<double>(std::max<std::size_t>(n, 1)));
    const int m = samples.size();
    const int panel_size = unit * std::clamp(static_cast<int>(panel_target / unit), 1, m / unit + 1);
    tables.along_y.resize(components);
    for (int row0 = 0; row0 < m; row0 += panel_size)
        for (int col0 = 0; col0 < m; col0 += panel_size) {
            const int rows = std::min(panel_size, m - row0);
            const int cols = std::min(panel_size, m - col0);
            if (!tile_needs_node(layer, plan, node, row0, col0, rows, cols)) continue;
            fill_axis_table(x_axis, layer.lambda_um, layer.grid, k.px, a_x, ones, col0, cols, tables.along_x);
            for (std::size_t c = 0; c < components; ++c)
                fill_axis_table(y_axis, layer.lambda_um, layer.grid, k.py, a_y, coefficients[c], row0, rows,
                                tables.along_y[c]);
            const int tile_rows = tables.along_y[0].blocks();
            const int tile_cols = tables.along_x.blocks();
            parallel_for(static_cast<std::size_t>(tile_rows) * tile_cols, 1, [&](std::size_t begin, std::size_t end) {
                for (std::size_t t = begin; t < end; ++t) {
                    const int r0 = row0 + static_cast<int>(t / tile_cols) * gabor::kTileRows;
                    const int c0 = col0 + static_cast<int>(t % tile_cols) * gabor::kTileCols;
                    const int tr = std::min(gabor::kTileRows, row0 + rows - r0);
                    const int tc = std::min(gabor::kTileCols, col0 + cols - c0);
                    if (!tile_needs_node(layer, plan, node, r0, c0, tr, tc)) continue;
                    product_tile(samples, plan, node, tables.along_x, tables.along_y, r0, c0, u);
                    for (int r = r0; r < r0 + tr; ++r)
                        for (int c = c0; c < c0 + tc; ++c) {
                            const DiskPoint p = samples.point(r, c);
                            if (!inside_unit_disk(p)) continue;
                            const std::size_t i = static_cast<std::size_t>(r) * m + c;
                            const double weight = plan.slices.weight(node, plan.xi3_at[i]);
                            if (weight == 0.0) continue;
                            std::complex<double> value = u[0][i];
                            if (components == 3) {
                                const gabor::TransformPoint point = transform_at(layer, p);
                                value -= point.xi2_gx * u[1][i] + point.xi2_gy * u[2][i];
                            }
                            field[i] += weight * value;
                        }
                }
            });
        }
}

// ξ3 per sample and the nodes: one (ξ3 = 2) for OHS and R-OHS; for GHS, R-GHS and Kirchhoff the
// nodes of choose_xi3_slices for the kernels' heights about their |w|-weighted mean.
NodePlan plan_nodes(const LayerSetup& layer, const gabor::FootprintKernels& kernels, double mean_height) {
    NodePlan plan;
    const LobeQuery& query = layer.query;
    FootprintSamples heights;  // the slice chooser reads weights and heights only
    heights.weight = kernels.arrays.weight;
    heights.height.resize(kernels.arrays.size());
    for (std::size_t i = 0; i < kernels.arrays.size(); ++i) heights.height[i] = kernels.arrays.height[i] - mean_height;
    heights.weight.resize(kernels.arrays.size());
    plan.slices = choose_xi3_slices(query.model, heights, layer.lambda_um, query.omega_i.z, query.omega_i.z + 1.0,
                                    layer.phase_error, kMaxXi3Nodes);
    const SampleGrid& samples = layer.samples;
    const int m = samples.size();
    plan.xi3_at.assign(static_cast<std::size_t>(m) * m, 0.0);
    for (int r = 0; r < m; ++r)
        for (int c = 0; c < m; ++c) {
            const DiskPoint p = samples.point(r, c);
            if (inside_unit_disk(p))
                plan.xi3_at[static_cast<std::size_t>(r) * m + c] =
                    xi3(query.model, query.omega_i, direction_from_disk(p.x, p.y));
        }
    return plan;
}

// The |w|-weighted mean kernel height: heights about it keep the phases the nodes interpolate small.
double mean_kernel_height(const KernelArrays& k) {
    double sum_w = 0.0, sum_wh = 0.0;
    for (std::size_t i = 0; i < k.size(); ++i) {
        sum_w += std::abs(k.weight[i]);
        sum_wh += std::abs(k.weight[i]) * k.height[i];
    }
    return sum_w > 0.0 ? sum_wh / sum_w : 0.0;
}

// f_r = ξ1/A_c |Σ_nodes w_node U_node|² at every sample (Yan 2018 eq. 16-17).
void product_layer(const LayerSetup& layer, const gabor::FootprintKernels& kernels, ProductTables& tables,
                   std::vector<double>& sums, int& node_count) {
    const bool sliced = phase_depends_on_outgoing(layer.query.model);
    // One node: keep the heights as gathered (a constant phase per layer changes nothing but rounding).
    const double mean_height = sliced ? mean_kernel_height(kernels.arrays) : 0.0;
    const NodePlan plan = plan_nodes(layer, kernels, mean_height);
    const int m = layer.samples.size();
    const std::size_t components = layer.query.model == DiffractionModel::kirchhoff ? 3 : 1;
    std::vector<std::vector<std::complex<double>>> u(components, std::vector<std::complex<double>>(std::size_t(m) * m));
    std::vector<std::complex<double>> field(std::size_t(m) * m);
    const int first = plan.slices.nodes_per_unit ? plan.slices.first : 0;
    const int last = plan.slices.nodes_per_unit ? plan.slices.last : 0;
    for (int node = first; node <= last; ++node) add_node(layer, kernels, plan, node, mean_height, tables, u, field);
    node_count = last - first + 1;
    parallel_for(m, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < m; ++c) {
                const DiskPoint p = layer.samples.point(static_cast<int>(r), c);
                if (!inside_unit_disk(p)) continue;
                const std::size_t i = r * m + c;
                sums[i] = transform_at(layer, p).brdf_scale * std::norm(field[i]);
            }
    });
}

// Second order: a chirped kernel's transform is not separable in v_x and v_y (H_xy couples them),
// so each sample sums every kernel's closed form (sum_transforms, the point query's sum) and ξ3
// is exact at each sample.
void chirped_layer(const LayerSetup& layer, const gabor::FootprintKernels& kernels, std::vector<double>& sums) {
    const int m = layer.samples.size();
    parallel_for(m, 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < m; ++c) {
                const DiskPoint p = layer.samples.point(static_cast<int>(r), c);
                if (!inside_unit_disk(p)) continue;
                const gabor::TransformPoint point = transform_at(layer, p);
                const std::complex<double> sum =
                    gabor::sum_transforms(kernels.arrays, 0, kernels.arrays.size(), point, layer.grid);
                sums[r * m + c] = point.brdf_scale * std::norm(sum);  // Yan 2018 eq. 16-17
            }
    });
}

void record_settings(const GaborSettings& settings, const KernelGrid& grid, const gabor::FootprintKernels& kernels,
                     const LobeQuery& query, LobeImage& image) {
    if (std::string warning = kernel_blur_warning(query.footprint, grid); !warning.empty())
        image.metadata["gabor.warning"] = std::move(warning);
    image.metadata["gabor.kernels_per_texel"] = std::to_string(settings.kernels_per_texel);
    image.metadata["gabor.order"] = std::to_string(settings.order);
    image.metadata["gabor.kernel_spacing_um"] = shortest_text(grid.spacing_um);
    image.metadata["gabor.kernel_sigma_um"] = shortest_text(grid.sigma_um);
    image.metadata["gabor.kernels"] = std::to_string(kernels.arrays.size());
    if (query.footprint.shape == FootprintShape::gaussian)
        image.metadata["gabor.footprint_truncation_sigmas"] = shortest_text(settings.footprint_sigmas);
}

// Second order: the spectral reach a kernel's chirp adds within 2σ_k of its centre (where its
// Gaussian is e^{−2} of its peak), ξ3 ρ(H'') 2√2 σ_k/λ at ξ3 ≤ 2 and the shortest wavelength;
// farther out the Gaussian is small enough that the FFT's slope padding covers it.
double chirp_bandwidth(const LobeQuery& query, const KernelGrid& grid, const gabor::FootprintKernels& kernels) {
    if (grid.order != 2) return 0.0;
    const KernelArrays& k = kernels.arrays;
    double radius = 0.0;
    for (std::size_t i = 0; i < k.size(); ++i)
        radius = std::max(radius, gabor::spectral_radius(k.curvature_xx[i], k.curvature_xy[i], k.curvature_yy[i]));
    const double shortest = *std::min_element(query.wavelengths_um.begin(), query.wavelengths_um.end());
    return 2.0 * radius * 2.0 * std::sqrt(2.0) * grid.sigma_um / shortest;
}

// The kernels summed in space on the FFT method's grid and transformed by its chirp-z transforms
// (gabor_field.hpp): the cost of an FFT image plus the splatting, for every model.
LobeImage gabor_lobe_on_grid(const LobeQuery& query, const GaborSettings& settings, const KernelGrid& grid,
                             const gabor::FootprintKernels& kernels) {
    const Point2 centre = query.footprint.centre_um;
    const ReflectionSource source =
        gabor::kernel_field_source(kernels.arrays, grid, centre, query.surface->height(centre.x, centre.y),
                                   query.model == DiffractionModel::kirchhoff, chirp_bandwidth(query, grid, kernels));
    std::map<double, gabor::FresnelAtWavelength> fresnel;
    for (double lambda : query.wavelengths_um) fresnel.emplace(lambda, gabor::FresnelAtWavelength(query.material, lambda));
    const ScatteringFactor xi1 = [&](const Vec3& psi, const Vec3& omega_o, double lambda) {
        // Yan 2018 Fig. 6: ξ1·λ², with F at cos θ_d = ω_i·h = |ψ|/2.
        return xi1_geometric(query.model, query.omega_i, omega_o) * fresnel.at(lambda)(0.5 * length(psi));
    };
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    scattering_layers(query, {query.omega_i, 1.0}, xi1, image, &source);
    record_settings(settings, grid, kernels, query, image);
    image.metadata["gabor.evaluation"] = "kernels summed on the fft grid (within 4 kernel sigmas), chirp-z transforms";
    return image;
}

}  // namespace

void check_footprint_width(const Footprint& footprint, const KernelGrid& grid) {
    if (footprint.shape == FootprintShape::gaussian && minor_sigma_um(footprint) < grid.sigma_um)
        throw Error("sigma_c " + shortest_text(minor_sigma_um(footprint)) + " um is below the kernels' width sigma_k " +
                    shortest_text(grid.sigma_um) + " um (kernels_per_texel " + std::to_string(grid.kernels_per_texel) +
                    "): the kernels cannot resolve the footprint; " + remedy(footprint, grid));
}

std::string kernel_blur_warning(const Footprint& footprint, const KernelGrid& grid) {
    const double blur = kernel_blur_factor(footprint, grid);
    if (blur >= 0.98) return {};
    return "the kernels' own blur (sigma_k " + shortest_text(grid.sigma_um) + " um against sigma_c " +
           shortest_text(minor_sigma_um(footprint)) + " um) keeps f = " + shortest_text(std::round(blur * 1e4) / 1e4) +
           " of the window's energy: the albedo is " + shortest_text(std::round((1.0 - blur) * 1e3) / 10) +
           "% low, as Yan 2018 eq. 16 weights each kernel by the window at its centre; " + remedy(footprint, grid);
}

LobeImage gabor_lobe(const LobeQuery& query) {
    const GaborSettings settings = gabor_settings(query);
    const BicubicInterpolant& surface = *query.surface;
    const KernelGrid grid = gabor::kernel_grid(surface.texel_um(), settings);
    const gabor::CoherenceWindow window(query.footprint, settings.footprint_sigmas);
    check_footprint_width(query.footprint, grid);
    const gabor::FootprintKernels kernels = gabor::gather_kernels(surface, grid, window, query.footprint.centre_um);
    if (kernels.arrays.size() == 0)
        throw Error("the footprint holds no kernel centre (kernel spacing " + shortest_text(grid.spacing_um) +
                    " um); use a larger footprint or more kernels_per_texel");
    const double phase_error = method_option_number(query, "phase_error", 0.01);
    if (!(phase_error > 0.0 && phase_error <= 1.0))
        throw Error("option phase_error must be in (0, 1], got " + shortest_text(phase_error));

    const std::string evaluation = method_option_text(query, "evaluation", "grid");
    if (evaluation != "grid" && evaluation != "products")
        throw Error("option evaluation must be grid or products, got '" + evaluation + "'");
    if (evaluation == "grid") return gabor_lobe_on_grid(query, settings, grid, kernels);

    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    const SampleGrid samples{query.resolution, query.supersample};
    const int m = samples.size();
    std::vector<double> sums(static_cast<std::size_t>(m) * m);
    std::vector<double> pixel_sums(static_cast<std::size_t>(query.resolution) * query.resolution);
    ProductTables tables;
    std::vector<std::string> nodes;
    for (std::size_t layer = 0; layer < query.wavelengths_um.size(); ++layer) {
        const double lambda = query.wavelengths_um[layer];
        const gabor::FresnelAtWavelength fresnel(query.material, lambda);
        const LayerSetup setup{query, grid, window.area_um2(), lambda, fresnel, samples, phase_error};
        std::fill(sums.begin(), sums.end(), 0.0);
        int node_count = 0;
        if (settings.order == 2)
            chirped_layer(setup, kernels, sums);
        else
            product_layer(setup, kernels, tables, sums, node_count);
        nodes.push_back(std::to_string(node_count));
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

    record_settings(settings, grid, kernels, query, image);
    image.metadata["gabor.kernel_truncation_sigmas"] = shortest_text(settings.kernel_sigmas);
    if (settings.order == 2) {
        image.metadata["gabor.evaluation"] = "every chirped kernel's closed-form transform summed at every sample";
        return image;
    }
    image.metadata["gabor.xi3_nodes"] = join(nodes, ";");
    if (phase_depends_on_outgoing(query.model)) image.metadata["gabor.phase_error"] = shortest_text(phase_error);
    image.metadata["gabor.evaluation"] = "banded separable matrix products, one per xi3 node";
    return image;
}

MethodEntry gabor_method() {
    MethodEntry entry{{"gabor",
             "Gabor kernels, one per cell of a regular grid, summed in closed form (default: second order, K = 1 per texel)",
             "Yan 2018 §4-5, eq. 16-17",
             {Quantity::brdf},
             {},
             {{"kernels_per_texel", "kernels per texel side K, an integer 1-16 (default 1)"},
              {"footprint_truncation", "drop kernels beyond this many sigma_c from the centre (default 3.25)"},
              {"kernel_truncation", "products evaluation: cut each kernel's transform at this many of its sigmas (default 3)"},
              {"order", "1: heights expanded to first order in each kernel (Yan 2018); 2: to second order, chirped "
                        "kernels (default 2)"},
              {"phase_error", "GHS, R-GHS, Kirchhoff: xi3 interpolation error bound, in flat-mirror peak amplitudes "
                              "(default 0.01)"},
              {"evaluation", "grid: kernels summed in space, transformed like fft (default; fast); products: the "
                             "closed-form sum of the kernels' transforms, cut at kernel_truncation"}},
             true},
            gabor_lobe,
            gabor_point_answers,
            gabor_point_field};
    // One kernel grid step along both axes (kernel_grid): rectangular texels are resampled first.
    entry.info.needs_square_texels = true;
    return entry;
}

}  // namespace glintscope
