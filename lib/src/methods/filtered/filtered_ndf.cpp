#include "methods/filtered/filtered_ndf.hpp"

#include <cmath>
#include <string>

#include "normal_density/normal_density.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "methods/pndf/pndf.hpp"

namespace glintscope {
namespace {

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
    // One σ in µm: as many taps along each axis as its spacing needs (dx ≠ dy is fine).
    const std::vector<double> taps = gaussian_taps(sigma_um / field.dx_um());
    const int radius = static_cast<int>(taps.size() / 2);
    const std::vector<double> taps_y = gaussian_taps(sigma_um / field.dy_um());
    const int radius_y = static_cast<int>(taps_y.size() / 2);
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
                for (int k = -radius_y; k <= radius_y; ++k)
                    sum += taps_y[k + radius_y] *
                           along_x[static_cast<std::size_t>(wrap(static_cast<long long>(r) + k, field.rows)) * field.cols + c];
                smoothed.at(static_cast<int>(r), c) = static_cast<float>(sum);
            }
    });
    return smoothed;
}

double filter_sigma_um(const LobeQuery& query) {
    const double sigma_f = method_option_length_um(query, "filter_sigma", 1.0);
    if (!(sigma_f >= 0.0 && sigma_f <= 0.25 * std::min(query.field->width_um(), query.field->height_um())))
        throw Error("option filter_sigma must be between 0 and a quarter of the heightfield, got " +
                    shortest_text(sigma_f) + " um");
    return sigma_f;
}

namespace {

LobeImage filtered_ndf(const LobeQuery& query) {
    const NormalDensitySettings settings = normal_density_settings(query);
    const double sigma_f = filter_sigma_um(query);
    const BicubicInterpolant surface(gaussian_smoothed(*query.field, sigma_f));
    LobeImage image = density_image(query, normal_density(surface, query.footprint, query.resolution, settings));
    image.metadata["filtered.filter_sigma_um"] = shortest_text(sigma_f);
    image.metadata["filtered.refinement"] = std::to_string(settings.refinement);
    image.metadata["filtered.intrinsic_roughness_rad"] = shortest_text(settings.intrinsic_roughness);
    return image;
}

}  // namespace

MethodEntry filtered_method() {
    MethodEntry entry;
    entry.info.name = "filtered";
    entry.info.description = "filtered NDF: normals of Gaussian-weighted plane fits of width sigma_f, accumulated exactly";
    entry.info.reference = "Dong 2015 sec. 5.1";
    entry.info.quantities = {Quantity::ndf};
    entry.info.ignored = {QueryField::incident, QueryField::wavelengths, QueryField::model, QueryField::material,
                          QueryField::supersample};
    entry.info.options = normal_density_options();
    entry.info.options.insert(entry.info.options.begin(),
                              {"filter_sigma", "plane-fit window sigma_f, a length; 0 gives the P-NDF (default 1um)"});
    entry.info.whole_field = true;
    entry.compute = filtered_ndf;
    return entry;
}

}  // namespace glintscope
