#include "glintscope/optics/diffraction_model.hpp"

#include <cmath>

#include "glintscope/core/error.hpp"

namespace glintscope {

DiffractionModel parse_diffraction_model(const std::string& name) {
    if (name == "ohs") return DiffractionModel::ohs;
    if (name == "ghs") return DiffractionModel::ghs;
    if (name == "rohs") return DiffractionModel::rohs;
    if (name == "rghs") return DiffractionModel::rghs;
    if (name == "kirchhoff") return DiffractionModel::kirchhoff;
    throw Error("unknown diffraction model '" + name + "' (expected ohs, ghs, rohs, rghs or kirchhoff)");
}

std::string to_string(DiffractionModel model) {
    switch (model) {
        case DiffractionModel::ohs: return "ohs";
        case DiffractionModel::ghs: return "ghs";
        case DiffractionModel::rohs: return "rohs";
        case DiffractionModel::rghs: return "rghs";
        case DiffractionModel::kirchhoff: return "kirchhoff";
    }
    return "rohs";
}

// Yan 2018 Fig. 6, column ξ1 (the F/λ² factor is applied by the caller).
double xi1_geometric(DiffractionModel model, Vec3 omega_i, Vec3 omega_o) {
    const double cos_i = std::fabs(omega_i.z);
    const double cos_o = std::fabs(omega_o.z);
    if (model == DiffractionModel::ohs || model == DiffractionModel::ghs) return cos_o / cos_i;
    const double psi_n = omega_i.z + omega_o.z;
    return psi_n * psi_n / (4.0 * cos_i * cos_o);
}

// Yan 2018 Fig. 6, column ξ3.
double xi3(DiffractionModel model, Vec3 omega_i, Vec3 omega_o) {
    if (model == DiffractionModel::ohs || model == DiffractionModel::rohs) return 2.0;
    return omega_i.z + omega_o.z;
}

bool phase_depends_on_outgoing(DiffractionModel model) {
    return model == DiffractionModel::ghs || model == DiffractionModel::rghs || model == DiffractionModel::kirchhoff;
}

// Yan 2018 Fig. 6, column ξ2: only the Kirchhoff model weights R(s) by the local slope.
double xi2(DiffractionModel model, Vec3 omega_i, Vec3 omega_o, double hx, double hy) {
    if (model != DiffractionModel::kirchhoff) return 1.0;
    const double psi_x = omega_i.x + omega_o.x;
    const double psi_y = omega_i.y + omega_o.y;
    const double psi_n = omega_i.z + omega_o.z;
    return 1.0 - (psi_x * hx + psi_y * hy) / psi_n;
}

}  // namespace glintscope
