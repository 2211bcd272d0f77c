// Spectral bins and CIE colorimetry (conventions.md "Spectra and colour", Yan 2018 §5): the
// shipped tables are the published ones, and the bin weights integrate them exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/optics/spectrum.hpp"

namespace glintscope {
namespace {

TEST(Spectrum, CmfTableReproducesThePublishedColumnSums) {
    // Validation sums published with the CIE dataset "Colour-matching functions of CIE 1931
    // standard colorimetric observer" (CIE 2019, doi:10.25039/CIE.DS.xvudnb9b), 360-830 nm at 1 nm.
    const CieTables& tables = cie_tables();
    ASSERT_EQ(tables.wavelength_nm.size(), 471u);
    EXPECT_EQ(tables.wavelength_nm.front(), 360.0);
    EXPECT_EQ(tables.wavelength_nm.back(), 830.0);
    XYZ total;
    for (const XYZ& row : tables.cmf) total = {total.X + row.X, total.Y + row.Y, total.Z + row.Z};
    EXPECT_NEAR(total.X, 106.865469489595, 1e-9);
    EXPECT_NEAR(total.Y, 106.8569171011719, 1e-9);
    EXPECT_NEAR(total.Z, 106.892251278636, 1e-9);
    EXPECT_EQ(tables.cmf[555 - 360].Y, 1.0);  // ȳ peaks at 1 at 555 nm by definition
}

TEST(Spectrum, D65TableIsNormalisedAt560nm) {
    const CieTables& tables = cie_tables();
    EXPECT_EQ(tables.d65[560 - 360], 100.0);
    double total = 0.0;
    for (double value : tables.d65) total += value;
    EXPECT_NEAR(total, 39187.6996, 1e-6);  // the CIE 1 nm D65 table summed over 360-830 nm
}

TEST(Spectrum, D65WithTheCmfsGivesTheD65WhitePoint) {
    for (int bins : {1, 8, 47}) {
        const Chromaticity white = chromaticity(spectral_weights(bins, Illuminant::d65).white);
        EXPECT_NEAR(white.x, 0.3127, 1e-4) << bins;
        EXPECT_NEAR(white.y, 0.3290, 1e-4) << bins;
    }
}

TEST(Spectrum, EqualEnergyWhiteIsAtOneThird) {
    // The CMFs are scaled so that the equal-energy spectrum has X = Y = Z.
    const Chromaticity white = chromaticity(spectral_weights(8, Illuminant::e).white);
    EXPECT_NEAR(white.x, 1.0 / 3.0, 1e-4);
    EXPECT_NEAR(white.y, 1.0 / 3.0, 1e-4);
}

TEST(Spectrum, FlatSpectrumHasUnitLuminanceForAnyBinning) {
    for (Illuminant illuminant : {Illuminant::d65, Illuminant::e})
        for (int bins : {1, 3, 8, 16, 470}) {
            const SpectralWeights weights = spectral_weights(bins, illuminant);
            ASSERT_EQ(weights.weights.size(), std::size_t(bins));
            const XYZ flat = integrate_to_xyz(weights, std::vector<double>(bins, 1.0));
            EXPECT_NEAR(flat.Y, 1.0, 1e-12);
            // Bins only split one integral: the white is the same for every binning.
            const XYZ reference = spectral_weights(1, illuminant).white;
            EXPECT_NEAR(flat.X, reference.X, 1e-12);
            EXPECT_NEAR(flat.Z, reference.Z, 1e-12);
        }
}

TEST(Spectrum, BinCentresAreMidpointsOfEqualBins) {
    const std::vector<double> centres = spectral_bin_centres_um(8);
    ASSERT_EQ(centres.size(), 8u);
    EXPECT_EQ(centres.front(), 0.389375);  // exactly the nearest double
    EXPECT_EQ(centres.back(), 0.800625);
    for (std::size_t i = 1; i < centres.size(); ++i) EXPECT_NEAR(centres[i] - centres[i - 1], 0.05875, 1e-15);
}

TEST(Spectrum, BinWeightsAreTheIntegralOverEachBin) {
    // Independent check: a fine midpoint sum of x̄ȳz̄·S over each bin, which sees the bin edges
    // (not on the 1 nm grid for 8 bins) only through the integrand.
    const SpectralWeights weights = spectral_weights(8, Illuminant::d65);
    std::vector<XYZ> sums(8);
    double total_y = 0.0;
    constexpr double step_um = 1e-6;  // 0.001 nm
    for (int i = 0; i < 8; ++i) {
        for (double lambda = weights.bin_edges_um[i] + 0.5 * step_um; lambda < weights.bin_edges_um[i + 1];
             lambda += step_um) {
            const XYZ c = cie_1931_cmf(lambda);
            const double s = illuminant_power(Illuminant::d65, lambda) * step_um;
            sums[i] = {sums[i].X + c.X * s, sums[i].Y + c.Y * s, sums[i].Z + c.Z * s};
        }
        total_y += sums[i].Y;
    }
    for (int i = 0; i < 8; ++i) {
        EXPECT_NEAR(weights.weights[i].X, sums[i].X / total_y, 2e-6) << i;
        EXPECT_NEAR(weights.weights[i].Y, sums[i].Y / total_y, 2e-6) << i;
        EXPECT_NEAR(weights.weights[i].Z, sums[i].Z / total_y, 2e-6) << i;
    }
}

TEST(Spectrum, NarrowBinHasTheChromaticityOfTheSpectralLocus) {
    // A 10 nm bin is nearly monochromatic: its colour lies next to the locus point at its centre.
    const SpectralWeights weights = spectral_weights(47, Illuminant::d65);
    for (int bin : {9, 24}) {  // 450-460 nm (blue) and 600-610 nm (orange)
        const double centre = weights.wavelengths_um[bin];
        const Chromaticity bin_colour = chromaticity(weights.weights[bin]);
        const Chromaticity locus = chromaticity(cie_1931_cmf(centre));
        EXPECT_NEAR(bin_colour.x, locus.x, 2e-3) << centre;
        EXPECT_NEAR(bin_colour.y, locus.y, 2e-3) << centre;
    }
}

TEST(Spectrum, ArbitraryWavelengthsReduceToEqualBinsForBinCentres) {
    const SpectralWeights equal = spectral_weights(8, Illuminant::d65);
    const SpectralWeights general = spectral_weights(spectral_bin_centres_um(8), Illuminant::d65);
    ASSERT_EQ(general.weights.size(), 8u);
    for (int i = 0; i < 8; ++i) {
        EXPECT_NEAR(general.weights[i].X, equal.weights[i].X, 1e-12);
        EXPECT_NEAR(general.weights[i].Y, equal.weights[i].Y, 1e-12);
        EXPECT_NEAR(general.weights[i].Z, equal.weights[i].Z, 1e-12);
    }
    // Uneven samples: bins reach halfway to the neighbours and out to 360 and 830 nm.
    const SpectralWeights uneven = spectral_weights({0.45, 0.55, 0.65}, Illuminant::e);
    const std::vector<double> edges{0.36, 0.5, 0.6, 0.83};
    ASSERT_EQ(uneven.bin_edges_um.size(), edges.size());
    for (std::size_t i = 0; i < edges.size(); ++i) EXPECT_NEAR(uneven.bin_edges_um[i], edges[i], 1e-15);
}

TEST(Spectrum, RejectsBadInput) {
    EXPECT_THROW(spectral_bin_centres_um(0), Error);
    EXPECT_THROW(spectral_weights(std::vector<double>{0.5, 0.9}, Illuminant::d65), Error);
    EXPECT_THROW(spectral_weights(std::vector<double>{0.6, 0.5}, Illuminant::d65), Error);
    EXPECT_THROW(spectral_weights(std::vector<double>{}, Illuminant::d65), Error);
    EXPECT_THROW(integrate_to_xyz(spectral_weights(8, Illuminant::d65), {1.0, 2.0}), Error);
    EXPECT_EQ(parse_illuminant("d65"), Illuminant::d65);
    EXPECT_EQ(parse_illuminant("E"), Illuminant::e);
    try {
        parse_illuminant("D50");
        FAIL() << "D50 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("D65, E"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace glintscope
