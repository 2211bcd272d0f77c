// A sinusoidal grating H = A sin(2π u/Λ), u = x cos θ + y sin θ: the simplest periodic surface,
// whose diffraction orders sit at sin θ_o − sin θ_i = nλ/Λ.
#include <cmath>

#include "generators.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope {

std::vector<float> sinusoidal_grating(const GridSpec& grid, const GratingParameters& parameters) {
    std::vector<float> heights(static_cast<std::size_t>(grid.rows) * grid.cols);
    const double wavenumber = 2.0 * pi / parameters.period_um;
    const double cos_angle = std::cos(parameters.angle_rad);
    const double sin_angle = std::sin(parameters.angle_rad);
    parallel_for(grid.rows, 64, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            // conventions.md: sample (r, c) sits at ((c + 0.5)·dx, (R − r − 0.5)·dy).
            const double y = (grid.rows - static_cast<double>(r) - 0.5) * grid.dy_um();
            for (int c = 0; c < grid.cols; ++c) {
                const double x = (c + 0.5) * grid.dx_um();
                heights[r * grid.cols + c] =
                    static_cast<float>(parameters.amplitude_um * std::sin(wavenumber * (x * cos_angle + y * sin_angle)));
            }
        }
    });
    return heights;
}

}  // namespace glintscope
