#include "glintscope/optics/material.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <complex>
#include <cstdio>

#include "core/embedded_data.hpp"
#include "glintscope/core/error.hpp"

namespace glintscope {
namespace {

struct MaterialTable {
    std::string name;
    std::string source;
    std::vector<double> wavelength_um;  // strictly increasing
    std::vector<ComplexIndex> index;
};

std::string format_um(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", value);
    return buffer;
}

MaterialTable load_material(const EmbeddedFile& file) {
    const std::string source = "data/" + std::string(file.path);
    const NumericTable table = parse_numeric_table(file.text, source);
    if (table.columns != std::vector<std::string>{"wavelength_um", "n", "k"})
        throw Error(source + ": expected the columns wavelength_um,n,k");
    MaterialTable material;
    const std::string file_name(file.path.substr(file.path.rfind('/') + 1));
    material.name = file_name.substr(0, file_name.size() - 4);
    material.source = table_comment(file.text);
    for (const std::vector<double>& row : table.rows) {
        if (!material.wavelength_um.empty() && !(row[0] > material.wavelength_um.back()))
            throw Error(source + ": wavelengths must increase");
        material.wavelength_um.push_back(row[0]);
        material.index.push_back({row[1], row[2]});
    }
    return material;
}

// Every data/materials/<symbol>.csv, parsed once.
const std::vector<MaterialTable>& materials() {
    static const std::vector<MaterialTable> tables = [] {
        std::vector<MaterialTable> loaded;
        for (const EmbeddedFile& file : embedded_data_files())
            if (file.path.starts_with("materials/") && file.path.ends_with(".csv")) loaded.push_back(load_material(file));
        return loaded;
    }();
    return tables;
}

bool same_name(const std::string& a, const std::string& b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
           });
}

const MaterialTable& find_material(const std::string& name) {
    for (const MaterialTable& material : materials())
        if (same_name(material.name, name)) return material;
    std::string known;
    for (const MaterialTable& material : materials()) {
        if (!known.empty()) known += ", ";
        known += material.name;
    }
    throw Error("unknown material '" + name + "' (available: " + known + ")");
}

}  // namespace

void check_material_name(const std::string& material) { find_material(material); }

std::vector<std::string> material_names() {
    std::vector<std::string> names;
    for (const MaterialTable& material : materials()) names.push_back(material.name);
    return names;
}

std::string material_source(const std::string& material) { return find_material(material).source; }

ComplexIndex complex_refractive_index(const std::string& material, double lambda_um) {
    const MaterialTable& table = find_material(material);
    const std::vector<double>& lambdas = table.wavelength_um;
    if (!(lambda_um >= lambdas.front() && lambda_um <= lambdas.back()))
        throw Error("material " + table.name + " has optical constants for " + format_um(lambdas.front()) + "-" +
                    format_um(lambdas.back()) + " um only, not for " + format_um(lambda_um) + " um");
    const std::size_t upper = std::max<std::size_t>(
        1, std::upper_bound(lambdas.begin(), lambdas.end(), lambda_um) - lambdas.begin());
    const std::size_t row = std::min(upper, lambdas.size() - 1) - 1;
    const double t = (lambda_um - lambdas[row]) / (lambdas[row + 1] - lambdas[row]);
    const ComplexIndex& a = table.index[row];
    const ComplexIndex& b = table.index[row + 1];
    return {a.n + t * (b.n - a.n), a.k + t * (b.k - a.k)};
}

double fresnel_conductor(ComplexIndex eta, double cos_theta) {
    if (std::isnan(cos_theta)) throw Error("Fresnel reflectance needs a finite cos(theta)");
    using Complex = std::complex<double>;
    const double cos_i = std::clamp(cos_theta, 0.0, 1.0);
    if (cos_i == 0.0) return 1.0;  // the grazing limit of both polarisations, also for n = 1
    const Complex n(eta.n, eta.k);
    // Snell's law with a complex index (Born & Wolf §14.2): sin θ_t = sin θ_i / n, and the
    // principal square root gives the transmitted wave that decays into the metal.
    const Complex sin2_t = (1.0 - cos_i * cos_i) / (n * n);
    const Complex cos_t = std::sqrt(1.0 - sin2_t);
    const Complex r_s = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    const Complex r_p = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    return 0.5 * (std::norm(r_s) + std::norm(r_p));
}

double fresnel_reflectance(const std::string& material, double lambda_um, double cos_theta) {
    if (material.empty()) return 1.0;
    return fresnel_conductor(complex_refractive_index(material, lambda_um), cos_theta);
}

}  // namespace glintscope
