#include "glintscope/fit/ndf_fit_slices.hpp"

#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/lobe/slice.hpp"

namespace glintscope {
namespace {

std::vector<double> layer_zero(const std::vector<SlicePoint>& slice) {
    std::vector<double> values;
    for (const SlicePoint& point : slice) values.push_back(point.values.at(0));
    return values;
}

}  // namespace

std::vector<NdfFitSlice> ndf_fit_slices(const LobeImage& ndf, const std::vector<NdfFit>& fits, int samples) {
    if (fits.empty()) throw Error("fit slices need at least one fitted model");
    if (samples < 3) throw Error("fit slices need at least 3 samples");
    // The model's images at the data's resolution, sliced by the same bilinear rule as the data, so
    // that a perfect fit draws the same curve.
    std::vector<LobeImage> model_images;
    for (const NdfFit& fit : fits) model_images.push_back(model_ndf_image(fit.model, ndf.resolution));
    // The α_x axis lies along (cos θ_z, −sin θ_z) (ndf_models.hpp).
    const double along = -fits.front().model.parameters.theta_z;
    std::vector<NdfFitSlice> slices;
    for (const double angle : {along, along + 0.5 * pi}) {
        NdfFitSlice slice;
        slice.angle_deg = angle * 180.0 / pi;
        const std::vector<SlicePoint> points = image_slice(ndf, angle, samples);
        for (const SlicePoint& point : points) slice.theta_deg.push_back(point.theta_deg);
        slice.data = layer_zero(points);
        for (const LobeImage& image : model_images) slice.models.push_back(layer_zero(image_slice(image, angle, samples)));
        slices.push_back(std::move(slice));
    }
    return slices;
}

}  // namespace glintscope
