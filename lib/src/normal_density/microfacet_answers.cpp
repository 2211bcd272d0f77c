#include "normal_density/microfacet_answers.hpp"

#include <utility>

#include "core/lazy.hpp"
#include "numerics/disk_distribution.hpp"

namespace glintscope {
namespace {

struct Microfacet {
    explicit Microfacet(MicrofacetTable made, std::size_t layers)
        : table(std::move(made)), wavelengths(layers),
          normals([this] { return make_disk_distribution(table.density.resolution, 1, table.density.values); }) {}

    MicrofacetTable table;
    std::size_t wavelengths = 1;
    Lazy<DiskDistribution> normals;  // h ∝ D(h) dA_h, piecewise constant over the table's pixels

    std::vector<double> eval(Vec3 omega_i, Vec3 omega_o) const {
        const Vec3 h = normalize(omega_i + omega_o);
        const double shadowing = table.shadowing ? table.shadowing(omega_i, omega_o, h) : 1.0;
        return microfacet_value(table.density.at(h.x, h.y), shadowing, omega_i, omega_o, h, table.indices, wavelengths);
    }

    DirectionSample sample(Vec3 omega_i, double u1, double u2) const {
        const auto point = sample_disk(normals.get(), u1, u2);
        if (!point) return {};
        return reflected_sample(omega_i, *point, disk_density(normals.get(), point->x, point->y));
    }

    double pdf(Vec3 omega_i, Vec3 omega_o) const {
        const Vec3 h = normalize(omega_i + omega_o);
        return reflection_pdf(disk_density(normals.get(), h.x, h.y), h, omega_o);
    }
};

}  // namespace

double reflection_pdf(double disk_density_of_h, Vec3 h, Vec3 omega_o) {
    const double cos_oh = dot(omega_o, h);
    if (cos_oh <= 0.0) return 0.0;
    return disk_density_of_h * h.z / (4.0 * cos_oh);  // dω_h/dω_o = 1/(4 ω_o·h) (Walter 2007 eq. 14), dA_h = h_z dω_h
}

DirectionSample reflected_sample(Vec3 omega_i, DiskPoint h_disk, double disk_density_of_h) {
    const Vec3 h = direction_from_disk(h_disk.x, h_disk.y);
    const double cos_ih = dot(omega_i, h);
    const Vec3 omega_o = 2.0 * cos_ih * h - omega_i;  // the mirror direction about h
    if (cos_ih <= 0.0 || omega_o.z <= 0.0) return {};
    return {omega_o, reflection_pdf(disk_density_of_h, h, omega_o)};
}

std::vector<double> microfacet_value(double density, double shadowing, Vec3 omega_i, Vec3 omega_o, Vec3 h,
                                     const std::vector<ComplexIndex>& indices, std::size_t wavelengths) {
    const double common = density * shadowing / (4.0 * omega_i.z * omega_o.z);  // Dong 2015 eq. 1
    std::vector<double> f(wavelengths, common);
    for (std::size_t k = 0; k < indices.size(); ++k) f[k] *= fresnel_conductor(indices[k], dot(omega_i, h));
    return f;
}

std::vector<ComplexIndex> refractive_indices(const LobeQuery& query) {
    std::vector<ComplexIndex> indices;
    if (!query.material.name.empty())
        for (double lambda : query.wavelengths_um) indices.push_back(complex_refractive_index(query.material.name, lambda));
    return indices;
}

PointAnswers microfacet_answers(MicrofacetTable table, std::size_t wavelengths) {
    // The sampling table is made on the first sample or pdf: eval alone never pays for it.
    std::shared_ptr<const Microfacet> shared = std::make_shared<const Microfacet>(std::move(table), wavelengths);
    return {[shared](Vec3 i, Vec3 o) { return shared->eval(i, o); },
            [shared](Vec3 i, double u1, double u2) { return shared->sample(i, u1, u2); },
            [shared](Vec3 i, Vec3 o) { return shared->pdf(i, o); }};
}

}  // namespace glintscope
