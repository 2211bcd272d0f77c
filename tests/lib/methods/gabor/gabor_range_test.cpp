// Far-away footprint centres: the kernel spans stay inside their buffers (exact integer
// clamps), and queries beyond ±1e6 µm are refused before any method runs.
#include <gtest/gtest.h>

#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/lobe/query.hpp"
#include "methods/gabor/gabor_kernels.hpp"

namespace glintscope {
namespace {

TEST(GaborRange, KernelIndexClampIsExactBeyondTwoToThe53) {
    const long long lo = (1ll << 53) + 1;  // not a double: double(lo) rounds down to 2^53
    const long long hi = lo + 7;
    EXPECT_EQ(gabor::clamp_kernel_index(static_cast<double>(lo), lo, hi), lo);
    EXPECT_EQ(gabor::clamp_kernel_index(1e300, lo, hi), hi);
    EXPECT_EQ(gabor::clamp_kernel_index(-1e300, lo, hi), lo);
    EXPECT_EQ(gabor::clamp_kernel_index(5.0, 2, 9), 5);
}

TEST(GaborRange, RowSpanStaysInsideItsBlockAtAHugeCentre) {
    Footprint footprint;
    footprint.sigma_um = 5.0;
    const gabor::CoherenceWindow window(footprint, 3.25);
    gabor::KernelGrid grid;  // l = 1 µm
    const double centre_x = 1e17;
    const long long lo = static_cast<long long>(centre_x) - 4, hi = lo + 7;  // one 8-kernel block
    long long first = 0, last = -1;
    if (window.row_span(grid, centre_x, 0.0, lo, hi, first, last)) {
        EXPECT_GE(first, lo);
        EXPECT_LE(last, hi);
        EXPECT_LE(last - first + 1, 8);
    }
}

TEST(GaborRange, CentresBeyondOneMetreAreRefusedByValidation) {
    LobeQuery query;
    set_heightfield(query, make_heightfield(16, 16, 1.0));
    query.footprint.sigma_um = 2.0;
    query.resolution = 8;
    query.footprint.centre_um = {1e17, 0.0};
    try {
        compute_lobe("gabor", query);
        FAIL() << "centre 1e17 um accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("within +-1e6 um"), std::string::npos) << e.what();
    }
    query.footprint.centre_um = {1e6, -1e6};  // the bound itself is valid
    EXPECT_NO_THROW(validate(query));
}

}  // namespace
}  // namespace glintscope
