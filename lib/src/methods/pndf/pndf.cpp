#include "methods/pndf/pndf.hpp"

#include <memory>
#include <optional>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "normal_density/normal_bounds_tree.hpp"

namespace glintscope {

std::vector<MethodOption> normal_density_options() {
    return {{"intrinsic_roughness", "radians: Gaussian blur in normal space of that width (Yan 2014) (default 0)"},
            {"refinement", "least cells per texel along each axis, 1-64 (default 1)"},
            {"tolerance", "pixels: cells are divided until their image is this close to affine, 0 keeps exactly "
                          "the refinement (default 0.02, whole field 0.1)"}};
}

NormalDensitySettings normal_density_settings(const LobeQuery& query) {
    NormalDensitySettings settings;
    settings.refinement = method_option_integer(query, "refinement", settings.refinement, 1, kMaxRefinement);
    // A whole field sums a million texels whose small displacement errors average out: 0.1 pixel
    // keeps it within 1% relative L2 of the converged NDF (docs/geometric.md) at a fifth the cost.
    const double tolerance = query.footprint.shape == FootprintShape::whole ? 0.1 : settings.tolerance_pixels;
    settings.tolerance_pixels = method_option_number(query, "tolerance", tolerance);
    if (!(settings.tolerance_pixels >= 0.0 && settings.tolerance_pixels <= 10.0))
        throw Error("option tolerance must be between 0 and 10 pixels, got " + shortest_text(settings.tolerance_pixels));
    settings.intrinsic_roughness = method_option_number(query, "intrinsic_roughness", 0.0);
    if (!(settings.intrinsic_roughness >= 0.0 && settings.intrinsic_roughness <= 1.0))
        throw Error("option intrinsic_roughness must be between 0 and 1 radian, got " +
                    shortest_text(settings.intrinsic_roughness));
    return settings;
}

LobeImage density_image(const LobeQuery& query, const std::vector<double>& density) {
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um, Quantity::ndf);
    for (std::size_t k = 0; k < density.size(); ++k) image.values[k] = static_cast<float>(density[k]);
    copy_first_layer_to_all(image);
    return image;
}

namespace {

LobeImage patch_ndf(const LobeQuery& query) {
    const NormalDensitySettings settings = normal_density_settings(query);
    LobeImage image =
        density_image(query, normal_density(*query.surface, query.footprint, query.resolution, settings));
    image.metadata["pndf.refinement"] = std::to_string(settings.refinement);
    image.metadata["pndf.tolerance_pixels"] = shortest_text(settings.tolerance_pixels);
    image.metadata["pndf.intrinsic_roughness_rad"] = shortest_text(settings.intrinsic_roughness);
    if (query.footprint.shape == FootprintShape::gaussian)
        image.metadata["pndf.weight_sigma_um"] = shortest_text(footprint_weight_sigma_um(query.footprint));
    return image;
}

// D(h) for any footprint from one tree over the field (eval(·, h): an NDF's point answer), and
// without intrinsic roughness h drawn with that same density (sample(·, u1, u2), pdf(·, h) per
// unit solid angle of h), so that sample, pdf and eval are one distribution; with it, the Ndf
// samples its image.
PointAnswersAt pndf_point_field(const LobeQuery& query) {
    auto tree = std::make_shared<const NormalBoundsTree>(
        make_normal_bounds_tree(query.surface, normal_density_settings(query), query.resolution));
    const std::size_t layers = query.wavelengths_um.size();
    return [tree, layers](const Footprint& footprint) -> PointAnswers {
        PointAnswers answers;
        answers.eval = [tree, footprint, layers](Vec3, Vec3 h) {
            return std::vector<double>(layers, point_normal_density(*tree, footprint, {h.x, h.y}));
        };
        if (tree->intrinsic_roughness > 0.0) return answers;
        auto normals = std::make_shared<const LazyNormalSampler>(tree, footprint);
        answers.sample = [normals](Vec3, double u1, double u2) -> DirectionSample {
            const std::optional<NormalDraw> drawn = normals->draw(u1, u2);
            if (!drawn) return {};
            const Vec3 h = direction_from_disk(drawn->normal.x, drawn->normal.y);
            return {h, drawn->density * h.z};  // dA on the disk = h_z dω_h
        };
        answers.pdf = [normals](Vec3, Vec3 h) { return normals->density({h.x, h.y}) * h.z; };
        return answers;
    };
}

}  // namespace

MethodEntry pndf_method() {
    MethodEntry entry;
    entry.info.name = "pndf";
    entry.info.description = "exact patch NDF: footprint-weighted density of the surface normals, no sampling noise";
    entry.info.reference = "Dong 2015 eq. 2 (the P-NDF of Yan 2014 for a footprint)";
    entry.info.quantities = {Quantity::ndf};
    entry.info.ignored = {QueryField::incident, QueryField::wavelengths, QueryField::model, QueryField::material,
                          QueryField::supersample};
    entry.info.options = normal_density_options();
    entry.info.whole_field = true;
    entry.info.rotated_boxes = true;
    entry.compute = patch_ndf;
    entry.point_field = pndf_point_field;
    return entry;
}

}  // namespace glintscope
