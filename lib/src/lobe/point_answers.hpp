#pragma once
// What a method may answer for single directions beyond its images, for the BSDF contract
// (glintscope/bsdf/bsdf.hpp): made once per footprint from a query (its ω_i and supersampling
// unused), then called from many threads at once. A method without them, or a member left
// empty, is answered from its own lobe images (bsdf/).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "glintscope/core/geometry.hpp"
#include "glintscope/lobe/footprint.hpp"

namespace glintscope {

struct DirectionSample {
    Vec3 direction;    // ω_o
    double pdf = 0.0;  // per unit solid angle of ω_o; 0: no direction (e.g. reflected below the horizon)
};

// A sample with eval(ω_i, ω_o) per wavelength at its direction (empty: not computed).
struct EvaluatedSample {
    DirectionSample sample;
    std::vector<double> f_r;
};

struct PointAnswers {
    // f_r(ω_i, ω_o) per query wavelength for unit directions above the horizon: what the image
    // holds at a pixel centre at supersample 1. A method answering ndf: D(h) for eval(·, h).
    std::function<std::vector<double>(Vec3 omega_i, Vec3 omega_o)> eval;
    // A sampler and its exact pdf (both or neither). A method answering ndf: h drawn by
    // sample(·, u1, u2) and its density per unit solid angle of h, pdf(·, h), the same density
    // as its eval (pdf ∝ D(h) h_z).
    std::function<DirectionSample(Vec3 omega_i, double u1, double u2)> sample;
    std::function<double(Vec3 omega_i, Vec3 omega_o)> pdf;
    // `sample` with f_r at the sampled direction, for a method that computes the two in one pass
    // (sharing their sums); empty: the BSDF calls sample, then eval for the weight.
    std::function<EvaluatedSample(Vec3 omega_i, double u1, double u2)> sample_with_f_r = nullptr;
    // ∫ f_r cosθ_o dω_o per wavelength by the BSDF's rule (the image's disk sum at supersample
    // kAlbedoSupersample over eval), where the method computes it faster than eval at every
    // sub-pixel; empty: the BSDF sums eval itself.
    std::function<std::vector<double>(Vec3 omega_i)> albedo = nullptr;
    // f_r at wavelengths of the caller's choice (µm, positive and finite), for a point query that
    // takes any λ; without it only the query's wavelengths can be asked for.
    std::function<std::vector<double>(Vec3 omega_i, Vec3 omega_o, const std::vector<double>& wavelengths_um)>
        eval_at_wavelengths = nullptr;
    // eval at each of several ω_i (unit; those below the horizon give 0) for one unit ω_o above
    // it, direction-major ([d · wavelengths + w]), equal bit for bit to eval direction by
    // direction, for a method that shares work across the directions (a renderer's lights at one
    // shading point); empty: the BSDF calls eval per direction.
    std::function<std::vector<double>(const std::vector<Vec3>& omegas_i, Vec3 omega_o)> eval_incident = nullptr;
    // What the method finds doubtful in these answers, for every direction (its images record
    // the same as "METHOD.warning", e.g. gabor's kernel blur at a narrow footprint); empty: nothing.
    std::string warning;
    // What the members above may point into without owning it (kept alive with them), so that
    // their captures stay small enough to be stored inside the std::function.
    std::shared_ptr<const void> owner = nullptr;
};

// The supersampling of the albedo's quadrature of a point query's eval (bsdf.hpp).
inline constexpr int kAlbedoSupersample = 4;

// A method's point answers for any footprint of the query's heightfield: built once from the
// query (its footprint, ω_i and supersampling unused), `at` is cheap and safe from many threads.
// Renderers need a BSDF at every shading point, each with its own footprint, so the costly part
// (a hierarchy over the whole heightfield) is built once and answers every footprint.
using PointAnswersAt = std::function<PointAnswers(const Footprint& footprint)>;

}  // namespace glintscope
