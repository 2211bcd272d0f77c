// Spatially varying ellipsoid parameters (Dong 2015 §9): one fit per patch, five maps.
#include <OpenImageIO/imageio.h>

#include <cmath>

#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/maps/ellipsoid_maps.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {

EllipsoidMaps fit_ellipsoid_maps(int rows, int cols, const std::function<LobeImage(int row, int col)>& patch_ndf) {
    if (rows < 1 || cols < 1) throw Error("patches: need at least one row and one column of patches");
    EllipsoidMaps maps{rows, cols, {}, {}};
    for (int row = 0; row < rows; ++row)
        for (int col = 0; col < cols; ++col) {
            const NdfFit fit = fit_ndf(patch_ndf(row, col), NdfModelKind::ellipsoid);
            maps.parameters.push_back(fit.model.parameters);
            maps.relative_error.push_back(fit.relative_error);
        }
    return maps;
}

EllipsoidMaps fit_ellipsoid_maps(const LobeQuery& query, const std::string& method, double patch_um) {
    if (!query.field) throw Error("heightfield: a patch fit needs a heightfield");
    if (!(patch_um > 0.0) || patch_um > query.field->width_um() || patch_um > query.field->height_um())
        throw Error("patch_um: must be positive and fit in the field, got " + shortest_text(patch_um));
    const int cols = int(std::floor(query.field->width_um() / patch_um));
    const int rows = int(std::floor(query.field->height_um() / patch_um));
    const double top = query.field->height_um();
    return fit_ellipsoid_maps(rows, cols, [&](int row, int col) {
        LobeQuery patch = query;
        patch.quantity = Quantity::ndf;
        patch.footprint.shape = FootprintShape::box;
        patch.footprint.size_um = patch_um;
        // Map view: patch row 0 is at the top, the largest y (conventions.md).
        patch.footprint.centre_um = {(col + 0.5) * patch_um, top - (row + 0.5) * patch_um};
        return compute_lobe(method, patch);
    });
}

void write_ellipsoid_maps_exr(const EllipsoidMaps& maps, const std::string& path) {
    const std::vector<std::string> names{"alpha_x", "alpha_y", "theta_x", "theta_y", "theta_z", "relative_error"};
    std::vector<float> pixels;
    for (std::size_t i = 0; i < maps.parameters.size(); ++i) {
        const EllipsoidNdf& p = maps.parameters[i];
        for (double v : {p.alpha_x, p.alpha_y, p.theta_x, p.theta_y, p.theta_z, maps.relative_error[i]})
            pixels.push_back(float(v));
    }
    OIIO::ImageSpec spec(maps.cols, maps.rows, int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.attribute("compression", "zip");
    spec.attribute("glintscope:ndf.model", "ellipsoid (Dong 2015 eq. 10-12), angles in radians");
    write_atomically(path, [&](const std::string& temporary) {
        auto output = OIIO::ImageOutput::create(temporary);
        if (!output || !output->open(temporary, spec) || !output->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) ||
            !output->close())
            throw Error("cannot write '" + path + "': " + OIIO::geterror());
    });
}

}  // namespace glintscope
