// Gabor point queries for any footprint: one pruning hierarchy per heightfield (Yan 2018 §5).
#include <memory>
#include <utility>

#include "gabor.hpp"
#include "glintscope/core/error.hpp"

namespace glintscope {

PointAnswersAt gabor_point_field(const LobeQuery& query) {
    for (const char* image_only : {"evaluation", "phase_error"})
        if (query.method_options.count(image_only))
            throw Error(std::string("option ") + image_only +
                        " applies to whole images; a point query sums the kernels' transforms in closed form");
    auto surface = std::make_shared<const GaborSurface>(query.surface, gabor_settings(query));
    const DiffractionModel model = query.model;
    const MaterialChoice material = query.material;
    auto wavelengths = std::make_shared<const std::vector<double>>(query.wavelengths_um);
    return [surface, model, material, wavelengths](const Footprint& footprint) {
        PointAnswers answers;
        answers.eval = [surface, model, material, wavelengths, footprint](Vec3 omega_i, Vec3 omega_o) {
            // Yan 2018 eq. 16-17 at every wavelength, the hierarchy walked once (§5 "Spectral rendering").
            return surface->f_r(GaborPointQuery{footprint, omega_i, omega_o, model, material}, *wavelengths);
        };
        return answers;
    };
}

}  // namespace glintscope
