// glintscope fit ellipsoid: parameters recovered from an NDF image, the fitted and residual
// images, and one-line errors.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <OpenImageIO/imageio.h>

#include "cli_runner.hpp"
#include "glintscope/output/lobe_output.hpp"
#include "glintscope/fit/ndf_fit.hpp"

namespace glintscope {
namespace {

using testing::run_cli;
using testing::TemporaryDirectory;

TEST(FitCommand, RecoversAnEllipsoidAndWritesItsImageAndResidual) {
    TemporaryDirectory directory;
    const EllipsoidNdf truth{0.3, 0.12, 0.1, -0.06, 0.5};
    const LobeImage ndf = model_ndf_image({NdfModelKind::ellipsoid, truth}, 96);
    write_lobe_exr(ndf, directory.file("ndf.exr"), {});
    const auto result = run_cli({"fit", "ellipsoid", directory.file("ndf.exr"), "-o", directory.file("fit.json"), "--image",
                                 directory.file("fitted.exr"), "--residual", directory.file("residual.exr"), "--plot",
                                 directory.file("fit.png"), "--models", "ellipsoid,beckmann"});
    ASSERT_EQ(result.exit_code, 0) << result.output;

    std::ifstream file(directory.file("fit.json"));
    const auto report = nlohmann::json::parse(file);
    ASSERT_EQ(report["fits"].size(), 2u);
    const auto& ellipsoid = report["fits"][0];
    EXPECT_EQ(ellipsoid["model"], "ellipsoid");
    EXPECT_NEAR(ellipsoid["alpha_x"].get<double>(), truth.alpha_x, 0.01 * truth.alpha_x);
    EXPECT_NEAR(ellipsoid["alpha_y"].get<double>(), truth.alpha_y, 0.01 * truth.alpha_y);
    EXPECT_NEAR(ellipsoid["theta_z_deg"].get<double>(), truth.theta_z * 180 / pi, 0.01 * truth.theta_z * 180 / pi);
    // Beckmann has neither skew nor rotation: it fits this NDF far worse.
    EXPECT_GT(report["fits"][1]["relative_error"].get<double>(), 10 * ellipsoid["relative_error"].get<double>());

    // The fitted image matches the input (float storage), the residual is their difference.
    const LobeImage fitted = load_lobe_exr(directory.file("fitted.exr"));
    const LobeImage residual = load_lobe_exr(directory.file("residual.exr"));
    double data_norm = 0.0, fit_error = 0.0, residual_mismatch = 0.0;
    for (std::size_t i = 0; i < ndf.values.size(); ++i) {
        data_norm += double(ndf.values[i]) * ndf.values[i];
        fit_error += std::pow(double(fitted.values[i]) - ndf.values[i], 2);
        residual_mismatch = std::max(residual_mismatch, std::abs(double(residual.values[i]) - (ndf.values[i] - fitted.values[i])));
    }
    EXPECT_LT(std::sqrt(fit_error / data_norm), 1e-3);
    EXPECT_EQ(residual_mismatch, 0.0);

    // The fit picture: two plots (along and across the principal axes) stacked, more tall than wide.
    const auto picture = OIIO::ImageInput::open(directory.file("fit.png"));
    ASSERT_TRUE(picture);
    EXPECT_GT(picture->spec().height, picture->spec().width);
}

TEST(FitCommand, APlotThatIsNotAPngFailsBeforeFitting) {
    TemporaryDirectory directory;
    write_lobe_exr(model_ndf_image({NdfModelKind::ggx, {0.2, 0.2, 0, 0, 0}}, 32), directory.file("ndf.exr"), {});
    const auto result = run_cli(
        {"fit", "ellipsoid", directory.file("ndf.exr"), "-o", directory.file("fit.json"), "--plot", directory.file("fit.jpg")});
    EXPECT_EQ(result.exit_code, 1);
    EXPECT_NE(result.output.find("--plot"), std::string::npos) << result.output;
    EXPECT_EQ(testing::count_entries(directory.path()), 1);  // nothing written
}

TEST(FitCommand, UnknownModelIsAOneLineError) {
    TemporaryDirectory directory;
    write_lobe_exr(model_ndf_image({NdfModelKind::ggx, {0.2, 0.2, 0, 0, 0}}, 32), directory.file("ndf.exr"), {});
    const auto result =
        run_cli({"fit", "ellipsoid", directory.file("ndf.exr"), "-o", directory.file("fit.json"), "--models", "phong"});
    EXPECT_EQ(result.exit_code, 1);
    EXPECT_NE(result.output.find("--models: unknown model 'phong'"), std::string::npos) << result.output;
    EXPECT_EQ(testing::count_entries(directory.path()), 1);  // nothing written

    const auto family = run_cli({"fit", "elipsoid", directory.file("ndf.exr"), "-o", directory.file("fit.json")});
    EXPECT_EQ(family.exit_code, 2) << family.output;  // a usage error
    EXPECT_NE(family.output.find("family"), std::string::npos) << family.output;
}

TEST(FitCommand, RefusesABrdfImage) {
    TemporaryDirectory directory;
    LobeImage brdf = model_ndf_image({NdfModelKind::ggx, {0.2, 0.2, 0, 0, 0}}, 32);
    brdf.quantity = Quantity::brdf;
    write_lobe_exr(brdf, directory.file("brdf.exr"), {});
    const auto result = run_cli({"fit", "ellipsoid", directory.file("brdf.exr"), "-o", directory.file("fit.json")});
    EXPECT_EQ(result.exit_code, 1);
    EXPECT_NE(result.output.find("ndf image"), std::string::npos) << result.output;
    EXPECT_EQ(testing::count_entries(directory.path()), 1);
}

}  // namespace
}  // namespace glintscope
