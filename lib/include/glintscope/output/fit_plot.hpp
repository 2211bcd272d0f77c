#pragma once
// The fit picture (`glintscope fit --plot`): an NDF against its fitted models along the principal
// axes (fit/ndf_fit_slices.hpp), log D against the polar angle, one plot per axis.
#include <string>
#include <vector>

#include "glintscope/fit/ndf_fit_slices.hpp"
#include "glintscope/output/plot.hpp"

namespace glintscope {

// One plot per slice: the data solid, each model dashed, with its relative error in the legend.
std::vector<Plot> ndf_fit_plots(const std::vector<NdfFitSlice>& slices, const std::vector<NdfFit>& fits,
                                const std::string& source);

}  // namespace glintscope
