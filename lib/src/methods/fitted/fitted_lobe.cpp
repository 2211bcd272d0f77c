#include "methods/fitted/fitted_lobe.hpp"

#include <algorithm>
#include <deque>
#include <memory>
#include <mutex>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/fit/ndf_fit.hpp"
#include "normal_density/microfacet_answers.hpp"
#include "normal_density/normal_density.hpp"

namespace glintscope {
namespace {

constexpr int kFitResolution = 128;

NdfModelKind fit_kind(const LobeQuery& query) {
    const std::string name = method_option_text(query, "fit", "beckmann");
    if (name != "beckmann" && name != "ggx") throw Error("option fit must be beckmann or ggx, got '" + name + "'");
    return parse_ndf_model_kind(name);
}

// The whole field's P-NDF (a large-area NDF, Dong 2015 §6), fitted by the model.
NdfFit fit_whole_field(const LobeQuery& query) {
    const NdfModelKind kind = fit_kind(query);  // a bad option before the NDF's work
    Footprint whole;
    whole.shape = FootprintShape::whole;
    NormalDensitySettings settings;
    settings.tolerance_pixels = 0.1;  // pndf's whole-field default: within 1% of the converged NDF
    const std::vector<double> density = normal_density(*query.surface, whole, kFitResolution, settings);
    LobeImage image = make_lobe_image(kFitResolution, {query.wavelengths_um.front()}, Quantity::ndf);
    std::transform(density.begin(), density.end(), image.values.begin(), [](double d) { return float(d); });
    return fit_ndf(image, kind);
}

// The fit depends only on the heights and the model, and make_bsdf is called per footprint: the
// last few fits are kept with their heightfields, matched by content (callers rebuild the query's
// interpolant and field copies, so pointers would not match).
struct CachedFit {
    std::shared_ptr<const Heightfield> field;
    NdfModelKind kind = NdfModelKind::beckmann;
    NdfFit fit;
};

bool same_heights(const Heightfield& a, const Heightfield& b) {
    return a.rows == b.rows && a.cols == b.cols && a.texel_um == b.texel_um && a.periodic == b.periodic &&
           a.heights_um == b.heights_um;
}

NdfFit cached_whole_field_fit(const LobeQuery& query) {
    constexpr std::size_t kKept = 4;
    static std::mutex mutex;
    static std::deque<CachedFit> kept;
    const NdfModelKind kind = fit_kind(query);
    const std::lock_guard lock(mutex);
    for (const CachedFit& entry : kept)
        if (entry.kind == kind && same_heights(*entry.field, *query.field)) return entry.fit;
    kept.push_front({query.field, kind, fit_whole_field(query)});
    if (kept.size() > kKept) kept.pop_back();
    return kept.front().fit;
}

struct FittedLobe {
    NdfModel model;
    std::vector<ComplexIndex> indices;
    std::size_t layers = 1;

    std::vector<double> eval(Vec3 omega_i, Vec3 omega_o) const {
        const Vec3 h = normalize(omega_i + omega_o);
        return microfacet_value(evaluate_ndf(model, h), 1.0, omega_i, omega_o, h, indices, layers);  // Dong 2015 eq. 1
    }
};

std::shared_ptr<const FittedLobe> fitted_lobe(const LobeQuery& query) {
    auto lobe = std::make_shared<FittedLobe>();
    lobe->model = cached_whole_field_fit(query).model;
    lobe->indices = refractive_indices(query);
    lobe->layers = query.wavelengths_um.size();
    return lobe;
}

LobeImage fitted_image(const LobeQuery& query) {
    const NdfFit fit = cached_whole_field_fit(query);
    const FittedLobe lobe{fit.model, refractive_indices(query), query.wavelengths_um.size()};
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    for (std::size_t l = 0; l < lobe.layers; ++l)
        fill_by_direction(image, l, query.supersample,
                          [&](DiskPoint p) { return lobe.eval(query.omega_i, direction_from_disk(p.x, p.y))[l]; });
    image.metadata["fitted.model"] = to_string(fit.model.kind);
    image.metadata["fitted.alpha_x"] = shortest_text(fit.model.parameters.alpha_x);
    image.metadata["fitted.alpha_y"] = shortest_text(fit.model.parameters.alpha_y);
    image.metadata["fitted.relative_error"] = shortest_text(fit.relative_error);
    return image;
}

PointAnswersAt fitted_point_field(const LobeQuery& query) {
    const std::shared_ptr<const FittedLobe> lobe = fitted_lobe(query);
    const PointAnswers answers{[lobe](Vec3 omega_i, Vec3 omega_o) { return lobe->eval(omega_i, omega_o); }, {}, {}};
    return [answers](const Footprint&) { return answers; };
}

}  // namespace

MethodEntry fitted_method() {
    MethodEntry entry;
    entry.info.name = "fitted";
    entry.info.description = "smooth microfacet baseline: Beckmann or GGX fitted to the whole field's NDF, no glints";
    entry.info.reference = "Dong 2015 eq. 1 and §8";
    entry.info.quantities = {Quantity::brdf};
    entry.info.ignored = {QueryField::footprint, QueryField::model};
    entry.info.options = {{"fit", "beckmann or ggx: the model fitted to the whole field's P-NDF (default beckmann)"}};
    entry.info.whole_field = true;
    entry.compute = fitted_image;
    entry.point_field = fitted_point_field;
    return entry;
}

}  // namespace glintscope
