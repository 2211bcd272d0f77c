#include "xi3_slices.hpp"

#include <cmath>
#include <string>

#include "glintscope/core/geometry.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {

double Xi3Slices::weight(int index, double xi3) const {
    if (!nodes_per_unit) return 1.0;
    const double u = xi3 * nodes_per_unit;
    const double base = std::floor(u);
    const double t = u - base;
    // Lagrange basis on the nodes base − 1, base, base + 1, base + 2.
    switch (index - static_cast<int>(base)) {
        case -1: return -t * (t - 1.0) * (t - 2.0) / 6.0;
        case 0: return (t + 1.0) * (t - 1.0) * (t - 2.0) / 2.0;
        case 1: return -(t + 1.0) * t * (t - 2.0) / 2.0;
        case 2: return (t + 1.0) * t * (t - 1.0) / 6.0;
        default: return 0.0;
    }
}

int Xi3Slices::lowest_node(double xi3) const {
    return nodes_per_unit ? static_cast<int>(std::floor(xi3 * nodes_per_unit)) - 1 : 0;
}

int Xi3Slices::highest_node(double xi3) const {
    return nodes_per_unit ? static_cast<int>(std::floor(xi3 * nodes_per_unit)) + 2 : 0;
}

Xi3Slices choose_xi3_slices(DiffractionModel model, const FootprintSamples& samples, double lambda_um,
                            double xi3_min, double xi3_max, double phase_error, int max_count) {
    Xi3Slices slices;
    if (!phase_depends_on_outgoing(model)) {
        slices.constant_xi3 = xi3(model, {0.0, 0.0, 1.0}, {0.0, 0.0, 1.0});
        return slices;
    }
    // ⟨α⁴⟩ weighted by |w|, α = 2π(H − H̄)/λ.
    double sum_w = 0.0, sum_w_alpha4 = 0.0;
    const double wavenumber = 2.0 * pi / lambda_um;
    for (std::size_t i = 0; i < samples.weight.size(); ++i) {
        const double alpha = wavenumber * samples.height[i];
        const double alpha2 = alpha * alpha;
        sum_w += std::fabs(samples.weight[i]);
        sum_w_alpha4 += std::fabs(samples.weight[i]) * alpha2 * alpha2;
    }
    const double mean_alpha4 = sum_w_alpha4 / sum_w;
    const double spacing = mean_alpha4 > 0.0 ? std::pow(phase_error / (3.0 / 128.0 * mean_alpha4), 0.25) : 1.0;
    const double nodes_per_unit = std::ceil(1.0 / std::min(spacing, 1.0));
    const double needed = (xi3_max - xi3_min) * nodes_per_unit + 4.0;
    if (!(needed <= max_count && nodes_per_unit <= max_count))
        throw Error("interpolating xi3 within phase_error " + shortest_text(phase_error) + " needs " +
                    std::to_string(static_cast<long long>(std::fmin(needed, 1e15))) + " transforms (more than " +
                    std::to_string(max_count) + "); raise phase_error or use a smoother surface");
    slices.nodes_per_unit = static_cast<int>(nodes_per_unit);
    slices.first = slices.lowest_node(xi3_min);
    slices.last = slices.highest_node(xi3_max);
    return slices;
}

}  // namespace glintscope
