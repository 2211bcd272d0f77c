// The table of methods: one line per method. A method's entry (name, description, reference,
// quantities, ignored query fields, options, compute function) lives in its own folder.
#include "pipeline/method_table.hpp"
#include "methods/discrete/discrete_lobe.hpp"
#include "methods/dk/kirchhoff_distribution.hpp"
#include "methods/fft/fft_lobe.hpp"
#include "methods/filtered/filtered_ndf.hpp"
#include "methods/fitted/fitted_lobe.hpp"
#include "methods/gabor/gabor.hpp"
#include "methods/geometric/geometric_lobe.hpp"
#include "methods/pndf/pndf.hpp"
#include "methods/stam/stam_lobe.hpp"

namespace glintscope {

const std::vector<MethodEntry>& method_table() {
    static const std::vector<MethodEntry> table = {
        fft_method(),
        gabor_method(),
        stam_method(),
        pndf_method(),
        filtered_method(),
        geometric_method(),
        dk_method(),
        discrete_method(),
        fitted_method(),
    };
    return table;
}

}  // namespace glintscope
