#pragma once
// Fitting parametric NDFs (ndf_models.hpp) to NDF images (image.hpp, quantity ndf), Dong 2015
// §8 (Fig. 12) and §9 (per-patch parameter maps). The fit minimises the squared difference of
// model and image integrated over the projected disk, Σ (D_model − D)² (2/N)²: every pixel weighs
// its projected solid angle, the measure in which both are unit-mass densities, so the fit is the
// L2 projection of the image onto the model family and no region is favoured by a chosen weight.
// The solver is NLopt's BOBYQA (bound-constrained, derivative-free; docs/ellipsoid.md).
#include <functional>
#include <string>
#include <vector>

#include "glintscope/lobe/image.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/fit/ndf_models.hpp"

namespace glintscope {

enum class NdfModelKind { ellipsoid, beckmann, ggx };

std::string to_string(NdfModelKind kind);
NdfModelKind parse_ndf_model_kind(const std::string& name);  // throws Error naming --models

// A fitted model. Beckmann and GGX use alpha_x and alpha_y only (their axes are x and y; the
// angles stay 0).
struct NdfModel {
    NdfModelKind kind = NdfModelKind::ellipsoid;
    EllipsoidNdf parameters;
};

double evaluate_ndf(const NdfModel& model, Vec3 m);

// The model drawn as a one-layer NDF image (pixel centres, like the fit).
LobeImage model_ndf_image(const NdfModel& model, int resolution);

struct NdfFit {
    NdfModel model;
    double relative_error = 0.0;  // √(Σ (D_model − D)²) / √(Σ D²) over the disk
    int evaluations = 0;          // objective evaluations the solver used
};

// Fits layer 0 of an NDF image (quantity ndf). Starts from the image's moments: the mean normal
// gives θ_x, θ_y, the principal axes of the normals' covariance θ_z and the two α.
NdfFit fit_ndf(const LobeImage& ndf, NdfModelKind kind);

// relative_error of a model against layer 0 of an NDF image.
double ndf_relative_error(const LobeImage& ndf, const NdfModel& model);

// JSON report of fits (parameters with angles in degrees, relative errors, weighting, solver).
std::string ndf_fits_json(const std::vector<NdfFit>& fits, const std::string& source);

}  // namespace glintscope
