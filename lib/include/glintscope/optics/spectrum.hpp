#pragma once
// Spectral sampling and CIE colorimetry (conventions.md "Spectra and colour", Yan 2018 §5).
//
// The visible range 360–830 nm is split into N equal bins and each bin is represented by the
// lobe at its midpoint. A spectral lobe becomes CIE 1931 XYZ through one weight per bin: the
// colour-matching functions times the illuminant, integrated exactly over the bin on the
// shipped 1 nm tables (both piecewise linear between table rows), normalised so that a spectrum
// equal to 1 at every wavelength has Y = 1. The tables are compiled into the library (data/).
#include <string>
#include <vector>

namespace glintscope {

constexpr double visible_min_um = 0.360;
constexpr double visible_max_um = 0.830;

// D65: CIE standard illuminant D65 (the default). E: the equal-energy spectrum.
enum class Illuminant { d65, e };

Illuminant parse_illuminant(const std::string& name);  // "d65" or "e", any case; else Error
std::string to_string(Illuminant illuminant);          // "D65" or "E"

struct XYZ {
    double X = 0.0;
    double Y = 0.0;
    double Z = 0.0;
};

struct Chromaticity {
    double x = 0.0;
    double y = 0.0;
};

Chromaticity chromaticity(XYZ colour);  // x = X/(X+Y+Z), y = Y/(X+Y+Z)

// The shipped tables at 1 nm from 360 to 830 nm (471 rows).
struct CieTables {
    std::vector<double> wavelength_nm;
    std::vector<XYZ> cmf;          // CIE 1931 2° colour-matching functions x̄, ȳ, z̄
    std::vector<double> d65;       // relative spectral power of D65, 100 at 560 nm
};
const CieTables& cie_tables();

// x̄, ȳ, z̄ at a wavelength, interpolated linearly between table rows; 0 outside 360–830 nm.
XYZ cie_1931_cmf(double lambda_um);

// Relative spectral power of an illuminant at a wavelength (D65 interpolated linearly, E = 1).
double illuminant_power(Illuminant illuminant, double lambda_um);

// Midpoints of N equal bins over 360–830 nm, in µm.
std::vector<double> spectral_bin_centres_um(int bins);

struct SpectralWeights {
    Illuminant illuminant = Illuminant::d65;
    std::vector<double> wavelengths_um;  // the sample wavelength of each bin
    std::vector<double> bin_edges_um;    // bin i spans [edges[i], edges[i+1]]
    std::vector<XYZ> weights;            // XYZ contributed by a value of 1 in bin i
    XYZ white;                           // Σ weights: the XYZ of a flat spectrum, white.Y = 1
};

// Weights for N equal bins (Yan 2018 §5); N from 1 to 4700.
SpectralWeights spectral_weights(int bins, Illuminant illuminant = Illuminant::d65);

// Weights for arbitrary sample wavelengths (strictly increasing, inside 360–830 nm): each sample
// stands for the bin between the midpoints to its neighbours, the outer bins reaching to 360 and
// 830 nm. For the centres of N equal bins these are exactly the N equal bins.
SpectralWeights spectral_weights(const std::vector<double>& wavelengths_um, Illuminant illuminant);

// Σ_i weights[i] · spectrum[i]; spectrum has one value per bin.
XYZ integrate_to_xyz(const SpectralWeights& weights, const std::vector<double>& spectrum);

}  // namespace glintscope
