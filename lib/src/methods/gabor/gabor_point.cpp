// Gabor's answers for single directions at any footprint (interface: lobe/point_answers.hpp):
// eval is GaborSurface's point query (Yan 2018 eq. 16–17 over the pruning hierarchy of §5), built
// once per heightfield; sample and pdf are the footprint's kernel mixture (gabor_sampling.hpp).
#include <memory>
#include <mutex>
#include <optional>

#include "gabor.hpp"
#include "gabor_kernels.hpp"
#include "gabor_sampling.hpp"

namespace glintscope {
namespace {

// One footprint's kernel mixture, gathered on the first sample or pdf: a renderer's shading point
// that is only evaluated never pays for interpolating the footprint's kernels.
class LazyMixture {
public:
    LazyMixture(std::shared_ptr<const BicubicInterpolant> surface, gabor::KernelGrid grid, Footprint footprint,
                double footprint_sigmas, DiffractionModel model, std::vector<double> wavelengths_um)
        : surface_(std::move(surface)), grid_(grid), footprint_(footprint), footprint_sigmas_(footprint_sigmas),
          model_(model), wavelengths_um_(std::move(wavelengths_um)) {}

    const gabor::KernelMixture& get() const {
        std::call_once(once_, [this] {
            const gabor::CoherenceWindow window(footprint_, footprint_sigmas_);
            mixture_.emplace(gabor::gather_kernels(*surface_, grid_, window, footprint_.centre_um).arrays, grid_,
                             model_, wavelengths_um_);
        });
        return *mixture_;
    }

private:
    std::shared_ptr<const BicubicInterpolant> surface_;
    gabor::KernelGrid grid_;
    Footprint footprint_;
    double footprint_sigmas_;
    DiffractionModel model_;
    std::vector<double> wavelengths_um_;
    mutable std::once_flag once_;
    mutable std::optional<gabor::KernelMixture> mixture_;
};

}  // namespace

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
        answers.eval_at_wavelengths = [surface, footprint, model, material](Vec3 omega_i, Vec3 omega_o,
                                                                          const std::vector<double>& chosen) {
            return surface->f_r({footprint, omega_i, omega_o, model, material}, chosen);
        };
        auto mixture = std::make_shared<const LazyMixture>(query.surface, grid, footprint,
                                                           surface->settings().footprint_sigmas, model, wavelengths);
        answers.sample = [mixture](Vec3 omega_i, double u1, double u2) { return mixture->get().sample(omega_i, u1, u2); };
        answers.pdf = [mixture](Vec3 omega_i, Vec3 omega_o) { return mixture->get().pdf(omega_i, omega_o); };
        return answers;
    };
}

}  // namespace glintscope
