#include "method_table.hpp"

#include "glintscope/fft_lobe.hpp"
#include "glintscope/gabor.hpp"

namespace glintscope {

const std::vector<LobeMethodEntry>& lobe_method_table() {
    static const std::vector<LobeMethodEntry> table = {
        {"fft", "ground truth: R* on a fine grid, exact chirp-z transform per pixel (Yan 2018 eq. 6)", fft_lobe},
        {"gabor", "Gabor kernels per cell of a regular grid, summed in closed form (Yan 2018 §4-5)", gabor_lobe},
    };
    return table;
}

}  // namespace glintscope
