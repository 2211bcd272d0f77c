// The albedo against incidence: a flat mirror reflects its Fresnel F at every θ_i by geometric
// optics and by the Kirchhoff wave lobe; on a rough surface at oblique incidence R-OHS's phase
// 2kH (Yan 2018 Fig. 6, ξ3 = 2, the phase of normal incidence) widens the lobe past the horizon
// and loses energy, where Kirchhoff's (ψ·n)kH keeps it near F.
#include "glintscope/validate/albedo.hpp"

#include <gtest/gtest.h>

#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"

namespace glintscope {
namespace {

LobeQuery gold_query(Heightfield field) {
    LobeQuery query;
    query.footprint.centre_um = field.centre_um();
    query.resolution = 64;
    query.wavelengths_um = {0.25};  // the wave lobe's blur λ/(2πσ_c) stays clear of the horizon at 80°
    query.material.name = "Au";
    set_heightfield(query, std::move(field));
    return query;
}

TEST(AlbedoVersusIncidence, AFlatMirrorReflectsItsFresnelReflectanceByGeometricAndKirchhoffOptics) {
    const AlbedoStudy study = albedo_versus_incidence(gold_query(make_heightfield(96, 96, 1.0)), {"geometric", "fft"},
                                                      {DiffractionModel::kirchhoff}, {0.0, 40.0, 80.0});
    ASSERT_EQ(study.curves.size(), 2u);
    EXPECT_FALSE(study.curves[0].model_applies);
    for (const AlbedoCurve& curve : study.curves)
        for (std::size_t k = 0; k < study.theta_i_deg.size(); ++k) {
            RecordProperty(curve.method + "_at_" + std::to_string(int(study.theta_i_deg[k])),
                           std::to_string(curve.albedo[k][0] / study.fresnel[k][0]));
            EXPECT_NEAR(curve.albedo[k][0], study.fresnel[k][0], 0.01 * study.fresnel[k][0])
                << curve.method << " at " << study.theta_i_deg[k] << " deg";
        }
}

TEST(AlbedoVersusIncidence, RohsLosesEnergyAtObliqueIncidenceWhereKirchhoffKeepsNearFresnel) {
    Recipe recipe = default_recipe("gaussian");  // rms slope 0.1 per axis over T = 10 µm
    recipe.grid = {96, 96, 1.0};
    recipe.gaussian.sigma_h_um = 0.7;
    LobeQuery query = gold_query(generate(recipe));
    query.wavelengths_um = {0.5};
    query.resolution = 48;
    const AlbedoStudy study =
        albedo_versus_incidence(query, {"fft"}, {DiffractionModel::rohs, DiffractionModel::kirchhoff}, {60.0});
    const double f = study.fresnel[0][0], rohs = study.curves[0].albedo[0][0], kirchhoff = study.curves[1].albedo[0][0];
    RecordProperty("rohs_over_f", std::to_string(rohs / f));
    RecordProperty("kirchhoff_over_f", std::to_string(kirchhoff / f));
    EXPECT_LT(rohs, 0.9 * f);
    EXPECT_NEAR(kirchhoff, f, 0.05 * f);
    EXPECT_THROW(albedo_versus_incidence(query, {"fft"}, {}, {90.0}), Error);
}

}  // namespace
}  // namespace glintscope
