// Gabor's answers for single directions (interface: lobe/point_answers.hpp). At any footprint
// (renderers' shading points): eval is GaborSurface's point query (Yan 2018 eq. 16–17 over the
// pruning hierarchy of §5), built once per heightfield. At one footprint (make_bsdf, many
// directions): eval sums the footprint's kernels through a SlopeIndex built once. Sample and pdf
// are the footprint's kernel mixture (gabor_sampling.hpp) over the footprint's slope index in
// both; at one footprint a sample also brings f_r, computed in the same pass as its pdf.
#include <cmath>
#include <complex>
#include <functional>
#include <memory>
#include <optional>

#include "gabor.hpp"
#include "gabor_kernels.hpp"
#include "gabor_sampling.hpp"
#include "gabor_slope_index.hpp"
#include "core/lazy.hpp"
#include "glintscope/core/error.hpp"

namespace glintscope {
namespace {

// One footprint's kernel mixture, made on the first sample or pdf: a renderer's shading point
// that is only evaluated never pays for interpolating the footprint's kernels.
using LazyMixture = Lazy<gabor::KernelMixture>;

void set_sampling(PointAnswers& answers, std::shared_ptr<const LazyMixture> mixture) {
    answers.sample = [mixture](Vec3 omega_i, double u1, double u2) { return mixture->get().sample(omega_i, u1, u2); };
    answers.pdf = [mixture](Vec3 omega_i, Vec3 omega_o) { return mixture->get().pdf(omega_i, omega_o); };
}

// f_r per wavelength from one footprint's slope index: ξ1/A_c |Σ_k w_k C_k F[g_k](v)|² (Yan 2018 eq. 16–17).
std::vector<double> indexed_f_r(const gabor::SlopeIndex& index, DiffractionModel model, const MaterialChoice& material,
                                double area_um2, Vec3 omega_i, Vec3 omega_o, const std::vector<double>& wavelengths_um) {
    for (const double lambda : wavelengths_um)
        if (!(lambda > 0.0 && std::isfinite(lambda))) throw Error("gabor: wavelengths must be positive and finite");
    std::vector<double> values(wavelengths_um.size(), 0.0);
    if (omega_i.z <= 0.0 || omega_o.z <= 0.0) return values;
    for (std::size_t i = 0; i < values.size(); ++i) {
        const double lambda = wavelengths_um[i];
        const gabor::TransformPoint point = gabor::transform_point(model, gabor::FresnelAtWavelength(material, lambda),
                                                                   omega_i, omega_o, lambda, area_um2);
        values[i] = point.brdf_scale * std::norm(index.sum(point));
    }
    return values;
}

// A sample of the footprint's mixture with f_r at its direction. Where the mixture's Gaussians
// share their exponents with the kernels' transforms (shared_norms: OHS, R-OHS), one scan of the
// index's cells finds the kernels eval sums and the pdf's others; at second order one pass over
// the first gives f_r and their part of the pdf, each kernel's exponential computed once, and the
// pdf adds its others. Elsewhere the pdf alone, and the BSDF evaluates f_r.
EvaluatedSample sample_with_f_r(const gabor::SlopeIndex& index, const gabor::KernelMixture& mixture,
                                DiffractionModel model, const MaterialChoice& material, double area_um2,
                                const std::vector<double>& wavelengths_um, Vec3 omega_i, double u1, double u2) {
    const std::optional<Vec3> omega_o = mixture.draw(omega_i, u1, u2);
    if (!omega_o) return {};
    if (!mixture.shared_norms(0)) return {{*omega_o, mixture.pdf(omega_i, *omega_o)}, {}};
    // Reused by each thread: no allocation per call.
    thread_local std::vector<gabor::KernelRun> transform_runs;
    thread_local std::vector<gabor::KernelRun> other_runs;
    std::vector<double> f_r(wavelengths_um.size(), 0.0);
    double density = 0.0;
    for (std::size_t layer = 0; layer < wavelengths_um.size(); ++layer) {
        const double lambda = wavelengths_um[layer];
        const gabor::TransformPoint point = gabor::transform_point(model, gabor::FresnelAtWavelength(material, lambda),
                                                                   omega_i, *omega_o, lambda, area_um2);
        transform_runs.clear();
        other_runs.clear();
        const gabor::ChirpFactors* factors =
            mixture.split_runs(omega_i, *omega_o, layer, point, transform_runs, other_runs);
        std::complex<double> sum = 0.0;
        if (factors) {
            sum = gabor::sum_transforms_and_density(index.kernels(), *factors, mixture.shared_norms(layer),
                                                    mixture.cut(), transform_runs, point, density);
        } else {  // first order: the terms, then their Gaussians
            for (const gabor::KernelRun& run : transform_runs)
                sum += gabor::sum_transforms(index.kernels(), run.begin, run.end, point, index.grid());
            density += mixture.layer_density(omega_i, *omega_o, layer, transform_runs);
        }
        f_r[layer] = point.brdf_scale * std::norm(sum);
        density += mixture.layer_density(omega_i, *omega_o, layer, other_runs);
    }
    return {{*omega_o, mixture.pdf_of_density(density, *omega_o)}, std::move(f_r)};
}

}  // namespace

PointAnswersAt gabor_point_field(const LobeQuery& query) {
    const GaborSettings settings = gabor_settings(query);
    const gabor::KernelGrid grid = gabor::kernel_grid(query.surface->texel_um(), settings);
    check_footprint_width(query.footprint, grid);
    auto surface = std::make_shared<const GaborSurface>(query.surface, settings);
    return [surface, grid, query](const Footprint& footprint) {
        PointAnswers answers;
        answers.warning = kernel_blur_warning(footprint, grid);
        const DiffractionModel model = query.model;
        const MaterialChoice material = query.material;
        const std::vector<double> wavelengths = query.wavelengths_um;
        answers.eval = [surface, footprint, model, material, wavelengths](Vec3 omega_i, Vec3 omega_o) {
            return surface->f_r({footprint, omega_i, omega_o, model, material}, wavelengths);
        };
        answers.eval_incident = [surface, footprint, model, material, wavelengths](const std::vector<Vec3>& omegas_i,
                                                                                  Vec3 omega_o) {
            return surface->f_r({footprint, omega_o, omega_o, model, material}, omegas_i, wavelengths);
        };
        answers.eval_at_wavelengths = [surface, footprint, model, material](Vec3 omega_i, Vec3 omega_o,
                                                                          const std::vector<double>& chosen) {
            return surface->f_r({footprint, omega_i, omega_o, model, material}, chosen);
        };
        const auto interpolant = query.surface;
        const double footprint_sigmas = surface->settings().footprint_sigmas;
        set_sampling(answers, std::make_shared<const LazyMixture>([=] {
                         const gabor::CoherenceWindow window(footprint, footprint_sigmas);
                         return gabor::KernelMixture(
                             std::make_shared<const gabor::SlopeIndex>(
                                 gabor::gather_kernels(*interpolant, grid, window, footprint.centre_um).arrays, grid),
                             model, wavelengths);
                     }));
        return answers;
    };
}

PointAnswers gabor_point_answers(const LobeQuery& query) {
    const GaborSettings settings = gabor_settings(query);
    const gabor::KernelGrid grid = gabor::kernel_grid(query.surface->texel_um(), settings);
    check_footprint_width(query.footprint, grid);
    const gabor::CoherenceWindow window(query.footprint, settings.footprint_sigmas);
    const DiffractionModel model = query.model;
    // Where ξ3 does not depend on the directions, each wavelength's ξ3/λ is known now: transform_point's.
    std::vector<double> prepared;
    if (!phase_depends_on_outgoing(model))
        for (const double lambda : query.wavelengths_um) prepared.push_back(xi3(model, {0, 0, 1}, {0, 0, 1}) / lambda);
    const auto index = std::make_shared<const gabor::SlopeIndex>(
        gabor::gather_kernels(*query.surface, grid, window, query.footprint.centre_um).arrays, grid, prepared);
    const double area = window.area_um2();
    const MaterialChoice material = query.material;
    const std::vector<double> wavelengths = query.wavelengths_um;
    PointAnswers answers;
    answers.eval = [=](Vec3 omega_i, Vec3 omega_o) {
        return indexed_f_r(*index, model, material, area, omega_i, omega_o, wavelengths);
    };
    answers.eval_at_wavelengths = [=](Vec3 omega_i, Vec3 omega_o, const std::vector<double>& chosen) {
        return indexed_f_r(*index, model, material, area, omega_i, omega_o, chosen);
    };
    answers.warning = kernel_blur_warning(query.footprint, grid);
    const auto mixture =
        std::make_shared<const LazyMixture>([=] { return gabor::KernelMixture(index, model, wavelengths); });
    set_sampling(answers, mixture);
    answers.sample_with_f_r = [=](Vec3 omega_i, double u1, double u2) {
        return sample_with_f_r(*index, mixture->get(), model, material, area, wavelengths, omega_i, u1, u2);
    };
    return answers;
}

}  // namespace glintscope
