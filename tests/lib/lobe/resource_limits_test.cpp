// Queries that would need more memory than a stated limit are refused, with the estimate, before
// anything is allocated; non-finite and negative values are refused everywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/lobe/query.hpp"
#include "lobe_queries.hpp"

namespace glintscope {
namespace {

using testing::compute_error;

TEST(ResourceLimits, AHugeImageIsRefusedWithItsSize) {
    LobeQuery query = testing::flat_query();
    query.resolution = 100000;  // 4·10^10 bytes per wavelength
    EXPECT_NE(compute_error("fft", query).find("(its image would need 40 GB)"), std::string::npos) << compute_error("fft", query);
    query.resolution = 8192;
    query.wavelengths_um.assign(16, 0.5);  // 8192²·16·4 bytes = 4.29 GB
    const std::string message = compute_error("fft", query);
    EXPECT_NE(message.find("would need 4.3 GB, beyond the 4 GB limit"), std::string::npos) << message;
    query.wavelengths_um.assign(14, 0.5);  // 3.76 GB: allowed by validation
    EXPECT_NO_THROW(validate(query));
}

TEST(ResourceLimits, AnFftGridBeyondItsLimitIsRefusedWithTheEstimate) {
    LobeQuery query = testing::flat_query();
    query.footprint.sigma_um = 30.0;  // support 3.25·30 µm: needs a periodic field
    query.method_options["step"] = "0.03um";  // 4σ window: 8000 samples per axis, 6.4·10^7 in all
    const std::string message = compute_error("fft", query);
    EXPECT_NE(message.find("GB (limit 2^23 samples, about 0.6 GB)"), std::string::npos) << message;
}

TEST(ResourceLimits, NonFiniteAndNegativeQueryValuesAreRefused) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (double bad : {nan, inf, -1.0}) {
        LobeQuery query = testing::flat_query();
        query.footprint.sigma_um = bad;
        EXPECT_THROW(validate(query), Error) << bad;
        query = testing::flat_query();
        query.wavelengths_um = {bad};
        EXPECT_THROW(validate(query), Error) << bad;
        query = testing::flat_query();
        query.footprint.shape = FootprintShape::box;
        query.footprint.size_um = bad;
        EXPECT_THROW(validate(query), Error) << bad;
        query = testing::flat_query();
        query.omega_i = {bad, 0.0, 1.0};
        EXPECT_THROW(validate(query), Error) << bad;
    }
    LobeQuery query = testing::flat_query();
    query.footprint.centre_um = {nan, 0.0};
    EXPECT_THROW(validate(query), Error);
}

}  // namespace
}  // namespace glintscope
