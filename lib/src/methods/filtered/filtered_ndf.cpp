#include "methods/filtered/filtered_ndf.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "geometric/normal_density.hpp"
#include "glintscope/error.hpp"
#include "glintscope/parallel.hpp"
#include "methods/pndf/pndf.hpp"

namespace glintscope {
namespace {

std::string format_number(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", value);
    return buffer;
}

constexpr double kFilterTruncationSigmas = 4.0;

std::vector<double> gaussian_taps(double sigma_texels) {
    const int radius = static_cast<int>(std::ceil(kFilterTruncationSigmas * sigma_texels));
    std::vector<double> taps(2 * radius + 1);
    double sum = 0.0;
    for (int k = -radius; k <= radius; ++k) sum += taps[k + radius] = std::exp(-0.5 * k * k / (sigma_texels * sigma_texels));
    for (double& tap : taps) tap /= sum;
    return taps;
}

int wrap(long long index, int count) {
    const long long r = index % count;
    return static_cast<int>(r < 0 ? r + count : r);
}

}  // namespace

Heightfield gaussian_smoothed(const Heightfield& field, double sigma_um) {
    if (sigma_um == 0.0) return field;
    const std::vector<double> taps = gaussian_taps(sigma_um / field.texel_um);
    const int radius = static_cast<int>(taps.size() / 2);
    std::vector<double> along_x(field.size());
    parallel_for(field.rows, 8, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < field.cols; ++c) {
                double sum = 0.0;
                for (int k = -radius; k <= radius; ++k)
                    sum += taps[k + radius] * field.at(static_cast<int>(r), wrap(c + k, field.cols));
                along_x[r * field.cols + c] = sum;
            }
    });
    Heightfield smoothed = field;
    parallel_for(field.rows, 8, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < field.cols; ++c) {
                double sum = 0.0;
                for (int k = -radius; k <= radius; ++k)
                    sum += taps[k + radius] *
                           along_x[static_cast<std::size_t>(wrap(static_cast<long long>(r) + k, field.rows)) * field.cols + c];
                smoothed.at(static_cast<int>(r), c) = static_cast<float>(sum);
            }
    });
    return smoothed;
}

LobeImage filtered_ndf(const LobeQuery& query) {
    if (!query.field) throw Error("filtered: the query has no heightfield");
    const NormalDensitySettings settings = normal_density_settings(query, "filtered", {"filter_sigma"});
    const double sigma_f = method_option_length_um(query, "filter_sigma", 1.0);
    if (!(sigma_f >= 0.0 && sigma_f <= 0.25 * std::min(query.field->width_um(), query.field->height_um())))
        throw Error("option filter_sigma must be between 0 and a quarter of the heightfield, got " +
                    format_number(sigma_f) + " um");
    const BicubicInterpolant surface(gaussian_smoothed(*query.field, sigma_f));
    LobeImage image = density_image(query, normal_density(surface, query.footprint, query.resolution, settings));
    image.metadata["filtered.filter_sigma_um"] = format_number(sigma_f);
    image.metadata["filtered.refinement"] = std::to_string(settings.refinement);
    image.metadata["filtered.intrinsic_roughness_rad"] = format_number(settings.intrinsic_roughness);
    return image;
}

}  // namespace glintscope
