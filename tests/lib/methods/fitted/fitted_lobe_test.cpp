// The smooth microfacet baseline (fitted_lobe.hpp): its BSDF is the closed-form microfacet BRDF
// F D / (4 cosθ_i cosθ_o) of the model fitted, independently here, to the whole field's P-NDF, and
// the fitted Beckmann roughness of a Gaussian surface is √2 × its rms slope.
#include "methods/fitted/fitted_lobe.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/fit/ndf_fit.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope {
namespace {

// A Gaussian random field (Gaussian correlation, 256² at 1 µm) whose slopes are Gaussian: its
// NDF is Beckmann's, α = √2 × the rms slope per axis (about 0.24 here).
const Heightfield& gaussian_field() {
    static const Heightfield field = [] {
        Recipe recipe;
        recipe.kind = "gaussian";
        recipe.grid = {256, 256, 1.0};
        recipe.gaussian.sigma_h_um = 0.6;
        recipe.gaussian.correlation_length_x_um = recipe.gaussian.correlation_length_y_um = 5.0;
        return generate(recipe);
    }();
    return field;
}

LobeQuery gaussian_query() {
    LobeQuery query;
    set_heightfield(query, gaussian_field());
    query.wavelengths_um = {0.5, 0.6};
    query.material.name = "Al";
    return query;
}

// The model fitted to pndf's whole-field image at 128², as the method's fit is documented.
NdfFit whole_field_fit(const LobeQuery& brdf_query, NdfModelKind kind) {
    LobeQuery query = brdf_query;
    query.quantity = Quantity::ndf;
    query.footprint.shape = FootprintShape::whole;
    query.resolution = 128;
    query.material = {};
    query.method_options.clear();
    return fit_ndf(compute_lobe("pndf", query), kind);
}

TEST(FittedLobe, IsTheClosedFormMicrofacetBrdfOfTheFitToTheWholeFieldsNdf) {
    for (const std::string fit : {"beckmann", "ggx"}) {
        LobeQuery query = gaussian_query();
        query.method_options["fit"] = fit;
        const NdfFit expected_fit = whole_field_fit(query, parse_ndf_model_kind(fit));
        const EllipsoidNdf& alpha = expected_fit.model.parameters;
        if (fit == "beckmann") {
            const SurfaceStatistics statistics = compute_statistics(gaussian_field());
            EXPECT_NEAR(alpha.alpha_x, std::sqrt(2.0) * statistics.rms_slope_x, 0.08 * alpha.alpha_x);
            EXPECT_NEAR(alpha.alpha_y, std::sqrt(2.0) * statistics.rms_slope_y, 0.08 * alpha.alpha_y);
        }
        const BsdfField field = make_bsdf_field("fitted", query);  // at(footprint) answers as make_bsdf
        const Bsdf bsdf = field.at(query.footprint);
        const Vec3 omega_i = direction_from_spherical(0.5, 0.3);
        for (const Vec3 omega_o : {direction_from_spherical(0.45, 3.3), direction_from_spherical(0.2, 1.0),
                                   direction_from_spherical(1.1, 2.0)}) {
            const Vec3 h = normalize(omega_i + omega_o);
            const double d = fit == "beckmann" ? beckmann_ndf(alpha.alpha_x, alpha.alpha_y, h)
                                               : ggx_ndf(alpha.alpha_x, alpha.alpha_y, h);
            const std::vector<double> f = bsdf.eval(omega_i, omega_o);
            ASSERT_EQ(f.size(), 2u);
            for (std::size_t k = 0; k < 2; ++k) {
                const double fresnel =
                    fresnel_conductor(complex_refractive_index("Al", query.wavelengths_um[k]), dot(omega_i, h));
                const double expected = fresnel * d / (4.0 * omega_i.z * omega_o.z);  // Dong 2015 eq. 1
                EXPECT_NEAR(f[k], expected, 1e-6 * expected) << fit << " layer " << k;
            }
        }
        // One baseline for every footprint: no glints.
        Footprint elsewhere = query.footprint;
        elsewhere.centre_um = {100.0, 700.0};
        EXPECT_EQ(field.at(elsewhere).eval(omega_i, omega_i), bsdf.eval(omega_i, omega_i));
    }
}

TEST(FittedLobe, ABadFitModelIsRefusedNamingTheOption) {
    LobeQuery query = gaussian_query();
    query.method_options["fit"] = "ellipsoid";
    try {
        compute_lobe("fitted", query);
        FAIL() << "accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("option fit"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace glintscope
