#pragma once
// 1-D slices through an image of the projected disk, through its centre (the normal n for an
// NDF), along a direction: the cross-brush and along-brush NDF profiles of Dong 2015 Fig. 9.
#include <string>
#include <vector>

#include "glintscope/lobe/image.hpp"

namespace glintscope {

struct SlicePoint {
    double position = 0.0;       // signed distance from the centre on the disk, in [−1, 1]
    double theta_deg = 0.0;      // signed polar angle of that point: asin(position)
    std::vector<double> values;  // per layer, bilinear between pixel centres
};

// `samples` points evenly over (−1, 1) along the direction at `angle_rad` from +x toward +y.
std::vector<SlicePoint> image_slice(const LobeImage& image, double angle_rad, int samples);

// "x", "y" or an angle in degrees ("30") as radians; throws Error otherwise.
double parse_slice_direction(const std::string& text);

// CSV: position, theta_deg, then one column per layer named by quantity and wavelength.
std::string slice_csv(const LobeImage& image, const std::vector<SlicePoint>& slice);

}  // namespace glintscope
