// Gabor's answers for single directions at any footprint (interface: lobe/point_answers.hpp):
// eval is GaborSurface's point query (Yan 2018 eq. 16–17 over the pruning hierarchy of §5), built
// once per heightfield; sample and pdf are the footprint's kernel mixture (gabor_sampling.hpp).
#include <memory>

#include "gabor.hpp"
#include "gabor_kernels.hpp"
#include "gabor_sampling.hpp"

namespace glintscope {

PointAnswersAt gabor_point_field(const LobeQuery& query) {
    const GaborSettings settings = gabor_settings(query);
    auto surface = std::make_shared<const GaborSurface>(query.surface, settings);
    const gabor::KernelGrid grid = gabor::kernel_grid(query.surface->texel_um(), settings);
    return [surface, grid, query](const Footprint& footprint) {
        PointAnswers answers;
        const DiffractionModel model = query.model;
        const MaterialChoice material = query.material;
        const std::vector<double> wavelengths = query.wavelengths_um;
        answers.eval = [surface, footprint, model, material, wavelengths](Vec3 omega_i, Vec3 omega_o) {
            return surface->f_r({footprint, omega_i, omega_o, model, material}, wavelengths);
        };
        const gabor::CoherenceWindow window(footprint, surface->settings().footprint_sigmas);
        auto mixture = std::make_shared<const gabor::KernelMixture>(
            gabor::gather_kernels(*query.surface, grid, window, footprint.centre_um).arrays, grid, model, wavelengths);
        answers.sample = [mixture](Vec3 omega_i, double u1, double u2) { return mixture->sample(omega_i, u1, u2); };
        answers.pdf = [mixture](Vec3 omega_i, Vec3 omega_o) { return mixture->pdf(omega_i, omega_o); };
        return answers;
    };
}

}  // namespace glintscope
