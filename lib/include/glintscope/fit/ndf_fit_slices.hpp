#pragma once
// An NDF image against its fitted models along the first model's principal axes, through n (the
// disk's centre): the slices a fit picture draws (`glintscope fit --plot`), so that a reader sees
// where a model departs from the data, the peak or the tails, along and across the anisotropy.
#include <vector>

#include "glintscope/fit/ndf_fit.hpp"
#include "glintscope/lobe/image.hpp"

namespace glintscope {

struct NdfFitSlice {
    double angle_deg = 0.0;                   // the slice's direction on the disk, from +x toward +y
    std::vector<double> theta_deg;            // signed polar angle of each point (asin of its disk position)
    std::vector<double> data;                 // layer 0 of the image, bilinear between pixel centres
    std::vector<std::vector<double>> models;  // per fit, its model drawn as an image and sliced alike
};

// Two slices: along the first fit's α_x axis (−θ_z: ndf_models.hpp) and across it, `samples`
// points each. Throws Error for no fits or fewer than 3 samples.
std::vector<NdfFitSlice> ndf_fit_slices(const LobeImage& ndf, const std::vector<NdfFit>& fits, int samples);

}  // namespace glintscope
