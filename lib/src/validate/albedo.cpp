#include "glintscope/validate/albedo.hpp"

#include <cmath>
#include <numeric>

#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/pipeline/pipeline.hpp"

namespace glintscope {

std::vector<double> default_albedo_angles() { return {0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0}; }

std::string curve_name(const AlbedoCurve& curve) {
    return curve.model_applies ? curve.method + ", " + to_string(curve.model) : curve.method;
}

std::vector<double> band_mean(const std::vector<std::vector<double>>& table) {
    std::vector<double> means;
    for (const std::vector<double>& row : table)
        means.push_back(std::accumulate(row.begin(), row.end(), 0.0) / double(row.size()));
    return means;
}

AlbedoStudy albedo_versus_incidence(const LobeQuery& query, const std::vector<std::string>& methods,
                                    const std::vector<DiffractionModel>& models,
                                    const std::vector<double>& theta_i_deg, const ProgressCallback& progress) {
    for (double theta : theta_i_deg)
        if (!(theta >= 0.0 && theta < 90.0))
            throw Error("albedo: incidence " + shortest_text(theta) + " deg is outside [0, 90)");
    const double phi_i = std::atan2(query.omega_i.y, query.omega_i.x);
    AlbedoStudy study{theta_i_deg, query.wavelengths_um, {}, {}};
    for (double theta : theta_i_deg) {
        std::vector<double> f;
        for (double lambda : query.wavelengths_um)
            f.push_back(fresnel_reflectance(query.material.name, lambda, std::cos(theta * pi / 180.0)));
        study.fresnel.push_back(f);
    }
    for (const std::string& method : methods) {
        const bool model_applies = !lobe_method(method).ignores(QueryField::model);
        for (DiffractionModel model : model_applies ? models : std::vector{query.model})
            study.curves.push_back({method, model, model_applies, {}});
    }
    for (const AlbedoCurve& curve : study.curves) {  // every request checked before the first computation
        LobeQuery checked = query;
        checked.model = curve.model;
        plan_lobe(curve.method, checked);
    }
    const std::size_t total = study.curves.size() * theta_i_deg.size();
    std::size_t done = 0;
    for (AlbedoCurve& curve : study.curves)
        for (double theta : theta_i_deg) {
            LobeQuery at = query;
            at.model = curve.model;
            at.omega_i = direction_from_spherical(theta * pi / 180.0, phi_i);
            const LobeImage image = compute_lobe(curve.method, at);
            std::vector<double> albedo;
            for (std::size_t layer = 0; layer < image.layers(); ++layer) albedo.push_back(disk_sum(image, layer));
            curve.albedo.push_back(albedo);
            if (progress) progress(++done, total, curve_name(curve) + ", theta_i " + shortest_text(theta) + " deg");
        }
    return study;
}

std::string albedo_csv(const AlbedoStudy& study) {
    std::vector<std::string> header = {"theta_i_deg", "fresnel"};
    for (const AlbedoCurve& curve : study.curves)
        header.push_back(curve.model_applies ? curve.method + "/" + to_string(curve.model) : curve.method);
    std::string csv = join(header, ",") + "\n";
    const std::vector<double> fresnel = band_mean(study.fresnel);
    for (std::size_t k = 0; k < study.theta_i_deg.size(); ++k) {
        std::vector<std::string> line = {shortest_text(study.theta_i_deg[k]), shortest_text(fresnel[k])};
        for (const AlbedoCurve& curve : study.curves) line.push_back(shortest_text(band_mean(curve.albedo)[k]));
        csv += join(line, ",") + "\n";
    }
    return csv;
}

}  // namespace glintscope
