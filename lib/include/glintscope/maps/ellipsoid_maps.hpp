#pragma once
// Dong 2015 §9: ellipsoid NDF parameters fitted per patch of a surface, as maps.
#include <functional>
#include <string>
#include <vector>

#include "glintscope/fit/ndf_fit.hpp"
#include "glintscope/lobe/query.hpp"

namespace glintscope {

// Ellipsoid parameters per patch, row-major, row 0 at the top (map view, largest y).
struct EllipsoidMaps {
    int rows = 0;
    int cols = 0;
    std::vector<EllipsoidNdf> parameters;
    std::vector<double> relative_error;
};

// Fits the ellipsoid to patch_ndf(row, col) for every patch (in order; each fit is serial and
// its objective parallel, so the maps do not depend on the thread count).
EllipsoidMaps fit_ellipsoid_maps(int rows, int cols, const std::function<LobeImage(int row, int col)>& patch_ndf);

// Patches of side patch_um tiling the query's field (whole patches only): each patch's NDF is
// compute_lobe(method, query) with a box footprint of that side centred on it.
EllipsoidMaps fit_ellipsoid_maps(const LobeQuery& query, const std::string& method, double patch_um);

// EXR with channels alpha_x, alpha_y, theta_x, theta_y, theta_z (radians) and relative_error.
void write_ellipsoid_maps_exr(const EllipsoidMaps& maps, const std::string& path);

}  // namespace glintscope
