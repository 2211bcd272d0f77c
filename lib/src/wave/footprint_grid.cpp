#include "footprint_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "glintscope/core/geometry.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

}  // namespace

FootprintExtent footprint_extent(const Footprint& footprint, double window_sigmas) {
    FootprintExtent extent;
    extent.centre_um = footprint.centre_um;
    if (footprint.shape == FootprintShape::box) {
        extent.box = true;
        const double width = box_width_um(footprint), height = box_height_um(footprint);
        extent.half_width_um = {0.5 * width, 0.5 * height};
        extent.area_um2 = width * height;
        extent.spectral_width = 1.0 / std::min(width, height);
    } else {
        extent.sigma_um = footprint.sigma_um;
        extent.half_width_um = {window_sigmas * footprint.sigma_um, window_sigmas * footprint.sigma_um};
        extent.area_um2 = pi * footprint.sigma_um * footprint.sigma_um;
        extent.spectral_width = 1.0 / (2.0 * pi * footprint.sigma_um);
    }
    return extent;
}

SampleAxis sample_axis(const FootprintExtent& extent, bool along_x, double step_um, int max_count) {
    const double half_width = along_x ? extent.half_width_um.x : extent.half_width_um.y;
    const double centre_um = along_x ? extent.centre_um.x : extent.centre_um.y;
    const double cells = 2.0 * half_width / step_um;
    if (!(cells < max_count))
        throw Error("a step of " + shortest_text(step_um) + " um needs more than " + std::to_string(max_count) +
                    " samples across the " + shortest_text(2.0 * half_width) +
                    " um footprint; use a larger step or a smaller footprint");
    if (extent.box) {
        const int count = std::max(1, static_cast<int>(std::ceil(cells)));
        const double step = 2.0 * half_width / count;
        return {count, step, centre_um - half_width + 0.5 * step};
    }
    const int half = std::max(1, static_cast<int>(std::ceil(0.5 * cells)));
    return {2 * half + 1, step_um, centre_um - half * step_um};
}

FootprintSamples sample_footprint(const BicubicInterpolant& surface, const FootprintExtent& extent, SampleAxis x,
                                  SampleAxis y, bool keep_slopes) {
    FootprintSamples samples;
    samples.x = x;
    samples.y = y;
    const std::size_t count = static_cast<std::size_t>(x.count) * y.count;
    samples.weight.resize(count);
    samples.height.resize(count);
    if (keep_slopes) {
        samples.slope_x.resize(count);
        samples.slope_y.resize(count);
    }
    // Per-row partial sums, combined in row order below: the same bits on any thread count.
    std::vector<double> row_weight(y.count), row_weighted_height(y.count), row_max_x(y.count), row_max_y(y.count);
    // The Gaussian is separable: w = w_x(x)·w_y(y); a box is 1 on every cell centre.
    const auto axis_weights = [&](const SampleAxis& axis, double centre) {
        std::vector<double> weights(axis.count, 1.0);
        if (!extent.box)
            for (int j = 0; j < axis.count; ++j) {
                const double d = axis.first_um + double(j) * axis.step_um - centre;
                weights[j] = std::exp(-0.5 * d * d / (extent.sigma_um * extent.sigma_um));
            }
        return weights;
    };
    const std::vector<double> weight_x = axis_weights(x, extent.centre_um.x);
    const std::vector<double> weight_y = axis_weights(y, extent.centre_um.y);
    parallel_for(y.count, 8, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const double sy = y.first_um + double(k) * y.step_um;
            double sum_w = 0.0, sum_wh = 0.0, max_x = 0.0, max_y = 0.0;
            for (int j = 0; j < x.count; ++j) {
                const double sx = x.first_um + double(j) * x.step_um;
                const SurfacePoint p = surface.evaluate(sx, sy);
                const std::size_t index = k * x.count + j;
                const double w = weight_x[j] * weight_y[k];
                samples.weight[index] = w;
                samples.height[index] = p.height;
                if (keep_slopes) {
                    samples.slope_x[index] = p.dh_dx;
                    samples.slope_y[index] = p.dh_dy;
                }
                sum_w += w;
                sum_wh += w * p.height;
                max_x = std::max(max_x, std::fabs(p.dh_dx));
                max_y = std::max(max_y, std::fabs(p.dh_dy));
            }
            row_weight[k] = sum_w;
            row_weighted_height[k] = sum_wh;
            row_max_x[k] = max_x;
            row_max_y[k] = max_y;
        }
    });
    double sum_w = 0.0, sum_wh = 0.0;
    for (int k = 0; k < y.count; ++k) {
        sum_w += row_weight[k];
        sum_wh += row_weighted_height[k];
        samples.max_slope_x = std::max(samples.max_slope_x, row_max_x[k]);
        samples.max_slope_y = std::max(samples.max_slope_y, row_max_y[k]);
    }
    // A constant height is a constant phase, invisible in |R̃*|² at fixed ξ3; removing the mean
    // keeps |H − H̄| (and so the error of interpolating between ξ3 slices) small.
    samples.mean_height_um = sum_wh / sum_w;
    for (double& h : samples.height) h -= samples.mean_height_um;
    return samples;
}

double alias_free_step(double psi_max, double xi3_max, double slope_max, double lambda_um, double guard,
                       double oversampling) {
    return 1.0 / ((psi_max + oversampling * xi3_max * slope_max) / lambda_um + guard);
}

}  // namespace glintscope
