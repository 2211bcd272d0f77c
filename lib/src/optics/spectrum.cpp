#include "glintscope/optics/spectrum.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "core/embedded_data.hpp"
#include "glintscope/core/error.hpp"

namespace glintscope {
namespace {

constexpr double table_start_nm = 360.0;
constexpr int table_rows = 471;  // 360..830 nm at 1 nm

std::string format_um(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", value);
    return buffer;
}

// Checks that a table is the 1 nm grid 360..830 with the expected columns.
void check_grid(const NumericTable& table, std::size_t columns, const std::string& source) {
    if (table.columns.size() != columns || table.rows.size() != table_rows)
        throw Error(source + ": expected " + std::to_string(table_rows) + " rows of " + std::to_string(columns) +
                    " columns (360-830 nm at 1 nm)");
    for (int i = 0; i < table_rows; ++i)
        if (table.rows[i][0] != table_start_nm + i)
            throw Error(source + ": row " + std::to_string(i + 1) + " is not at " +
                        std::to_string(360 + i) + " nm");
}

CieTables load_cie_tables() {
    const std::string cmf_path = "cie/CIE_xyz_1931_2deg.csv";
    const std::string d65_path = "cie/CIE_std_illum_D65.csv";
    const NumericTable cmf = parse_numeric_table(embedded_data(cmf_path), cmf_path);
    const NumericTable d65 = parse_numeric_table(embedded_data(d65_path), d65_path);
    check_grid(cmf, 4, cmf_path);
    check_grid(d65, 2, d65_path);
    CieTables tables;
    for (int i = 0; i < table_rows; ++i) {
        tables.wavelength_nm.push_back(cmf.rows[i][0]);
        tables.cmf.push_back({cmf.rows[i][1], cmf.rows[i][2], cmf.rows[i][3]});
        tables.d65.push_back(d65.rows[i][1]);
    }
    return tables;
}

// Table position of a wavelength in nm: row index and fraction toward the next row.
struct TablePosition {
    int row = 0;
    double fraction = 0.0;
};

TablePosition table_position(double lambda_nm) {
    const double offset = std::clamp(lambda_nm - table_start_nm, 0.0, double(table_rows - 1));
    const int row = std::min(int(offset), table_rows - 2);
    return {row, offset - row};
}

XYZ cmf_at_nm(double lambda_nm) {
    // The tolerance keeps bin edges converted from µm (0.36·1e3 may round below 360) inside.
    constexpr double tolerance_nm = 1e-9;
    if (!(lambda_nm >= table_start_nm - tolerance_nm && lambda_nm <= table_start_nm + table_rows - 1 + tolerance_nm))
        return {};
    const auto [row, t] = table_position(lambda_nm);
    const XYZ& a = cie_tables().cmf[row];
    const XYZ& b = cie_tables().cmf[row + 1];
    return {a.X + t * (b.X - a.X), a.Y + t * (b.Y - a.Y), a.Z + t * (b.Z - a.Z)};
}

double power_at_nm(Illuminant illuminant, double lambda_nm) {
    if (illuminant == Illuminant::e) return 1.0;
    const auto [row, t] = table_position(lambda_nm);
    const std::vector<double>& d65 = cie_tables().d65;
    return d65[row] + t * (d65[row + 1] - d65[row]);
}

XYZ scaled(XYZ colour, double s) { return {colour.X * s, colour.Y * s, colour.Z * s}; }
XYZ sum(XYZ a, XYZ b) { return {a.X + b.X, a.Y + b.Y, a.Z + b.Z}; }

// ∫ x̄ȳz̄(λ) S(λ) dλ over [a, b] nm. Between table rows both factors are linear, so their product
// is quadratic and Simpson's rule on each piece is exact.
XYZ integrate_bin(Illuminant illuminant, double a_nm, double b_nm) {
    const auto integrand = [illuminant](double lambda) {
        return scaled(cmf_at_nm(lambda), power_at_nm(illuminant, lambda));
    };
    XYZ total;
    double u = a_nm;
    while (u < b_nm) {
        const double v = std::min(b_nm, std::floor(u) + 1.0);
        const XYZ simpson = sum(sum(integrand(u), scaled(integrand(0.5 * (u + v)), 4.0)), integrand(v));
        total = sum(total, scaled(simpson, (v - u) / 6.0));
        u = v;
    }
    return total;
}

SpectralWeights weights_for_bins(std::vector<double> wavelengths_um, std::vector<double> edges_um,
                                 Illuminant illuminant) {
    SpectralWeights result;
    result.illuminant = illuminant;
    result.wavelengths_um = std::move(wavelengths_um);
    result.bin_edges_um = std::move(edges_um);
    for (std::size_t i = 0; i + 1 < result.bin_edges_um.size(); ++i)
        result.weights.push_back(
            integrate_bin(illuminant, result.bin_edges_um[i] * 1e3, result.bin_edges_um[i + 1] * 1e3));
    // conventions.md: a lobe equal to 1 at every wavelength maps to Y = 1.
    XYZ white;
    for (const XYZ& w : result.weights) white = sum(white, w);
    const double normalisation = 1.0 / white.Y;
    for (XYZ& w : result.weights) w = scaled(w, normalisation);
    result.white = {};
    for (const XYZ& w : result.weights) result.white = sum(result.white, w);
    return result;
}

}  // namespace

Illuminant parse_illuminant(const std::string& name) {
    std::string lower;
    for (char ch : name) lower += char(std::tolower(static_cast<unsigned char>(ch)));
    if (lower == "d65") return Illuminant::d65;
    if (lower == "e") return Illuminant::e;
    throw Error("unknown illuminant '" + name + "' (available: D65, E)");
}

std::string to_string(Illuminant illuminant) { return illuminant == Illuminant::d65 ? "D65" : "E"; }

Chromaticity chromaticity(XYZ colour) {
    const double total = colour.X + colour.Y + colour.Z;
    return {colour.X / total, colour.Y / total};
}

const CieTables& cie_tables() {
    static const CieTables tables = load_cie_tables();
    return tables;
}

XYZ cie_1931_cmf(double lambda_um) { return cmf_at_nm(lambda_um * 1e3); }

double illuminant_power(Illuminant illuminant, double lambda_um) { return power_at_nm(illuminant, lambda_um * 1e3); }

std::vector<double> spectral_bin_centres_um(int bins) {
    if (bins < 1 || bins > 4700) throw Error("number of spectral bins must be between 1 and 4700, got " +
                                             std::to_string(bins));
    // In nm first, so that round centres come out as the nearest doubles (389.375 nm → 0.389375).
    std::vector<double> centres;
    const double width_nm = (visible_max_um * 1e3 - visible_min_um * 1e3) / bins;
    for (int i = 0; i < bins; ++i) centres.push_back((visible_min_um * 1e3 + (i + 0.5) * width_nm) / 1e3);
    return centres;
}

SpectralWeights spectral_weights(int bins, Illuminant illuminant) {
    std::vector<double> centres = spectral_bin_centres_um(bins);
    std::vector<double> edges;
    const double width_nm = (visible_max_um * 1e3 - visible_min_um * 1e3) / bins;
    for (int i = 0; i <= bins; ++i)
        edges.push_back(i == bins ? visible_max_um : (visible_min_um * 1e3 + i * width_nm) / 1e3);
    return weights_for_bins(std::move(centres), std::move(edges), illuminant);
}

SpectralWeights spectral_weights(const std::vector<double>& wavelengths_um, Illuminant illuminant) {
    if (wavelengths_um.empty()) throw Error("spectral colour needs at least one wavelength");
    for (std::size_t i = 0; i < wavelengths_um.size(); ++i) {
        const double lambda = wavelengths_um[i];
        if (!(lambda >= visible_min_um && lambda <= visible_max_um))
            throw Error("spectral colour needs wavelengths within 0.36-0.83 um, got " + format_um(lambda) + " um");
        if (i > 0 && !(lambda > wavelengths_um[i - 1]))
            throw Error("spectral colour needs strictly increasing wavelengths, got " +
                        format_um(wavelengths_um[i - 1]) + " um then " + format_um(lambda) + " um");
    }
    std::vector<double> edges{visible_min_um};
    for (std::size_t i = 0; i + 1 < wavelengths_um.size(); ++i)
        edges.push_back(0.5 * (wavelengths_um[i] + wavelengths_um[i + 1]));
    edges.push_back(visible_max_um);
    return weights_for_bins(wavelengths_um, std::move(edges), illuminant);
}

XYZ integrate_to_xyz(const SpectralWeights& weights, const std::vector<double>& spectrum) {
    if (spectrum.size() != weights.weights.size())
        throw Error("spectrum has " + std::to_string(spectrum.size()) + " values for " +
                    std::to_string(weights.weights.size()) + " spectral bins");
    XYZ total;
    for (std::size_t i = 0; i < spectrum.size(); ++i) total = sum(total, scaled(weights.weights[i], spectrum[i]));
    return total;
}

}  // namespace glintscope
