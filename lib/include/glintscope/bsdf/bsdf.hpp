#pragma once
// Every method as a BSDF for renderers (conventions.md "Single directions"): one object per
// footprint, material and model, built once and then queried for many directions, immutable
// and safe to query from many threads at once. The terms of pbrt-v4 and Mitsuba 3:
//   eval   = pbrt f,        Mitsuba eval   (f_r in sr⁻¹, without the cosine)
//   sample = pbrt Sample_f, Mitsuba sample (ω_o, pdf per solid angle, weight f_r cosθ_o / pdf)
//   pdf    = pbrt PDF,      Mitsuba pdf
//   albedo = pbrt rho(ω_o)                 (∫ f_r cosθ_o dω_o)
// Directions are in the heightfield's frame (+z the mean normal); ω_i points toward the light,
// ω_o toward the viewer; either below the horizon gives f_r = 0 and pdf = 0.
//
// A method answers with its own point query and sampler where its folder supplies them
// (docs/renderer.md lists which), otherwise from its lobe image of the footprint: the image of
// ω_i at supersample 1, read at the pixel holding ω_o, and sampled as a piecewise-constant
// distribution on the projected disk with the exact pdf. Such tables are made on first use of
// an ω_i and the most recent ones are kept.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "glintscope/core/geometry.hpp"
#include "glintscope/lobe/query.hpp"

namespace glintscope {

struct BsdfSample {
    Vec3 omega_o;
    double pdf = 0.0;            // per unit solid angle of ω_o; 0: no direction (weights 0)
    std::vector<double> weight;  // f_r cosθ_o / pdf, one per wavelength of the query
};

class Bsdf {
public:
    // f_r(ω_i, ω_o) in sr⁻¹, one value per wavelength of the query.
    std::vector<double> eval(Vec3 omega_i, Vec3 omega_o) const;
    // f_r at the given wavelengths (µm), one value each: any wavelengths where the method's point
    // query takes any λ (any_wavelength()), otherwise only wavelengths the BSDF was made with;
    // throws Error naming the wavelength it cannot answer.
    std::vector<double> eval(Vec3 omega_i, Vec3 omega_o, const std::vector<double>& wavelengths_um) const;
    // f_r at each of several ω_i for one ω_o, direction-major: value [d · wavelengths + w] is
    // eval(omegas_i[d], omega_o)[w], bit for bit. A method's point query may share the work of its
    // footprint across the directions (gabor: one walk of its kernels; docs/renderer.md); every
    // other method evaluates them one by one.
    std::vector<double> eval_incident(const std::vector<Vec3>& omegas_i, Vec3 omega_o) const;
    // ω_o from two uniforms in [0, 1), shared by all wavelengths.
    BsdfSample sample(Vec3 omega_i, double u1, double u2) const;
    // The density per unit solid angle with which sample() returns ω_o.
    double pdf(Vec3 omega_i, Vec3 omega_o) const;
    // ∫ f_r cosθ_o dω_o per wavelength: the mean of sample()'s weight.
    std::vector<double> albedo(Vec3 omega_i) const;

    const std::string& method() const;
    const std::vector<double>& wavelengths_um() const;
    // Whether eval is the method's own point query (else its images' pixels); albedo is then the
    // image's disk sum at supersample 4, computed from eval (or, fft, by the method's images,
    // which compute the same sum).
    bool evaluates_directly() const;
    // Whether sample and pdf are the method's own sampler (else a pixel of its images).
    bool samples_directly() const;
    // Whether eval answers wavelengths other than the ones it was made with.
    bool any_wavelength() const;
    // Physics warnings that hold for every direction, one line each, as a lobe run of the same
    // method and footprint gives them: the footprint's (pipeline.hpp footprint_warnings) and the
    // method's own point query's, "METHOD: …" (gabor: its kernels' blur at a narrow footprint,
    // which lowers the albedo; stam: where its statistics do not hold). A BSDF answered from its
    // images (evaluates_directly() false) does not report those images' own warnings.
    std::vector<std::string> warnings() const;

    struct State;  // the method's parts and the tables (bsdf.cpp)
    explicit Bsdf(std::shared_ptr<State> state);

private:
    std::shared_ptr<State> state_;
};

// The BSDF of `method` for the query's footprint, heightfield, wavelengths, model, material,
// method options and resolution (of the tables); the query's ω_i and supersampling are not used.
// Checks the query as plan_lobe does and throws Error with one line naming the problem.
// A method with a point query for any footprint (docs/renderer.md) answers with it.
Bsdf make_bsdf(const std::string& method, const LobeQuery& query);

// A method's BSDFs for every footprint of one heightfield, for renderers whose every shading
// point has its own footprint: what is costly (a hierarchy over the whole heightfield) is built
// once from the query (its footprint, ω_i and supersampling unused), and `at` is then cheap and
// safe to call from many threads. at(query.footprint) answers exactly as make_bsdf(method, query)
// (but for an axis-aligned box of a field that answers_rotated_boxes()).
class BsdfField {
public:
    // Throws Error for an elliptical footprint if !answers_ellipses(), a rotated box if
    // !answers_rotated_boxes().
    Bsdf at(const Footprint& footprint) const;
    // Whether `at` takes elliptical Gaussian footprints: the method says so
    // (MethodInfo::elliptical_footprints) and its point query answers them with these settings.
    bool answers_ellipses() const;
    // Whether `at` takes rotated boxes (Footprint::axis_radians): the method says so
    // (MethodInfo::rotated_boxes) and its point query answers them with these settings. Such a
    // field answers axis-aligned boxes by its point query too (texels' lattice), where make_bsdf
    // answers them from images (lattice along the box's edges; docs/geometric.md).
    bool answers_rotated_boxes() const;
    const std::string& method() const;
    const std::vector<double>& wavelengths_um() const;

    struct State;
    explicit BsdfField(std::shared_ptr<const State> state);

private:
    std::shared_ptr<const State> state_;
};

// Checks the query as make_bsdf does; refuses in one line (Error) a method without a point query
// for any footprint.
BsdfField make_bsdf_field(const std::string& method, const LobeQuery& query);

// The methods make_bsdf_field accepts, in table order.
std::vector<std::string> bsdf_field_methods();

struct NdfSample {
    Vec3 h;
    double pdf = 0.0;  // per unit solid angle of h: D(h) h_z for a normalised D
};

// A method's normal distribution of one footprint as a function: D(h), and h sampled by
// projected area (pdf = D(h) h_z / ∫ D h_z dω), so that sample, pdf and eval are one density.
// Same sharing and threading as Bsdf. D is the method's point query where it has one (pndf:
// the exact D at h, whose mean over an image pixel is the pixel), else the pixel of its image
// holding h. h is drawn by the point query's own sampler where it has one (pndf without
// intrinsic roughness: a triangle of the footprint by its weight, a uniform point of its normal
// image; pdf = D(h) h_z × (truncated footprint weight / the triangles' weight, 1 ± 1e-5), its
// cumulative weights made on the first sample or pdf), else from the image (piecewise constant
// over its pixels, exact pdf: a box footprint, intrinsic roughness, a method without a point
// query); with intrinsic roughness eval is still the point query, so the pdf follows the
// image's pixels rather than eval's D.
class Ndf {
public:
    // D(h) per wavelength of the query (one value for wavelength-independent methods' copies).
    std::vector<double> eval(Vec3 h) const;
    // Whether eval is the method's point query (else its image's pixels).
    bool evaluates_directly() const;
    // Whether sample and pdf are the point query's own sampler (else its image's pixels).
    bool samples_directly() const;
    // h from two uniforms in [0, 1); pdf 0 (no h) where the drawn triangle's normal image is a
    // segment, which the point query gives no density.
    NdfSample sample(double u1, double u2) const;
    // The density per unit solid angle with which sample() returns h.
    double pdf(Vec3 h) const;
    // ∫ D(h) h_z dω_h per wavelength: 1 for a normalised NDF whose mass lies on the disk.
    std::vector<double> normalisation() const;

    struct State;
    explicit Ndf(std::shared_ptr<const State> state);

private:
    std::shared_ptr<const State> state_;
};

// The NDF of a method that answers quantity ndf, for the query's footprint.
Ndf make_ndf(const std::string& method, const LobeQuery& query);

}  // namespace glintscope
