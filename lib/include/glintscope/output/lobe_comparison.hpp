#pragma once
// Two lobe EXRs written by glintscope compared layer by layer (the `compare` command): the
// numbers of compare.hpp for each wavelength (or each of R, G, B of a colour EXR), a JSON report
// and a picture of the difference.
#include <cstddef>
#include <string>
#include <vector>

#include "glintscope/lobe/compare.hpp"
#include "glintscope/output/figure.hpp"
#include "glintscope/output/lobe_output.hpp"

namespace glintscope {

struct LobeFileComparison {
    std::string test_path;
    std::string reference_path;
    LobeExrLayers test;
    LobeExrLayers reference;
    std::vector<LayerComparison> layers;  // layer k is test.names[k]
};

// Reads both files (load_lobe_exr_layers) and compares them layer by layer (compare_layer).
// Throws Error in one line naming both files and what differs: quantity, size, layers, or the
// colour encoding of R, G, B.
LobeFileComparison compare_lobe_exrs(const std::string& test_path, const std::string& reference_path);

// The layer with the largest relative L2 (the first on ties).
std::size_t worst_layer(const LobeFileComparison& comparison);

// A table, one line per layer: relative L2, max |A − B| with its pixel and disk point, energy
// ratio, peak offset in pixels, log-space error.
std::string comparison_table(const LobeFileComparison& comparison);

// The report: both inputs (path, quantity, resolution, layers, method and query.* keys as
// recorded) and the numbers per layer, as JSON.
std::string comparison_json(const LobeFileComparison& comparison);

// write_difference_figure of the worst layer: A | B exposed alike | A − B on a diverging scale.
FigureLayout write_comparison_figure(const LobeFileComparison& comparison, const std::string& path);

}  // namespace glintscope
