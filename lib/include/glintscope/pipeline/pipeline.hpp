#pragma once
// The one request pipeline. Every caller — lobe, ndf, batch, validate, glints, fit maps, and the
// library's own users — runs a query with a method through run_lobe, so one query gives one image
// whoever asks: the library, not its callers, decides the supersampling, averages over the
// query's footprints and says what it chose and what looks wrong.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "glintscope/lobe/image.hpp"
#include "glintscope/lobe/method_info.hpp"
#include "glintscope/lobe/query.hpp"

namespace glintscope {

// Every method, in table order.
std::vector<MethodInfo> lobe_methods();

// The named method; throws Error listing the available ones for an unknown name.
MethodInfo lobe_method(const std::string& name);

// A query as it will run: what the caller left to the library resolved (the supersampling:
// LobeQuery::supersample 0 means automatic), the footprint centres it averages over, and a line
// for each choice the library made.
struct LobePlan {
    std::string method;
    LobeQuery query;             // supersample resolved (≥ 1)
    std::vector<Point2> centres;  // one per footprint averaged; the query's own centre when single
    std::vector<std::string> notes;
};

// Checks everything a run needs before any long computation — the method, the query, its
// quantity, footprint shape and border, the method's option keys — and resolves the plan.
// Throws Error with one line naming the problem.
LobePlan plan_lobe(const std::string& method, const LobeQuery& query);

struct LobeRun {
    LobeImage image;
    std::vector<std::string> notes;     // the plan's choices, one line each, to be said once
    std::vector<std::string> warnings;  // physics warnings about the query, the image and the method's own ("METHOD.warning")
};

// Called after each footprint of an averaged request with (done, total); for a single footprint
// per pass of the method's heavy loops (core/parallel.hpp: ProgressScope) with the chunks done of
// that pass's total: a count that falls back starts the next pass.
using RunProgress = std::function<void(std::size_t done, std::size_t total)>;

// Plans and runs: one footprint, or the mean over the plan's centres (pixel by pixel, in order:
// deterministic). The image's metadata holds the planned query (query_keys.hpp), fields the
// method ignores as "not applicable", "method", "method.reference", "quantity", "version",
// "supersample.rule" and, when averaged, "footprints.count" and the centres' bounding box.
// Errors from the method come prefixed with its name.
LobeRun run_lobe(const std::string& method, const LobeQuery& query, const RunProgress& progress = {});

// run_lobe's image, for callers that print nothing.
LobeImage compute_lobe(const std::string& method, const LobeQuery& query);

// The supersampling the pipeline chooses when the query leaves it automatic: for a wave-optics
// method, enough that the coherence blur λ/(2πσ_c) spans 1.5 sub-pixels (at most 8); 1 otherwise.
int recommended_supersample(const std::string& method, const LobeQuery& query);

// Physics warnings about a planned query for a method, one line each: a coherence blur below a
// sub-pixel that point-samples a wave lobe (its albedo and peak are then off), the footprint's
// (footprint_warnings), incidence beyond the models' validity (shadowing is ignored).
std::vector<std::string> query_warnings(const std::string& method, const LobeQuery& query);

// The warnings about a footprint at the given wavelengths, which hold for every direction (a
// BSDF's, bsdf.hpp): a wave-optics footprint below the wavelength, whose own diffraction sends
// much of the light beyond the hemisphere, where the scalar models no longer hold.
std::vector<std::string> footprint_warnings(const std::string& method, const Footprint& footprint,
                                            const std::vector<double>& wavelengths_um);

// Warnings about a computed image: a BRDF albedo above the material's Fresnel reflectance
// F(θ_i) (1 without a material) by more than 2%, naming the term of the method or model that
// creates the energy (e.g. R-OHS's ξ1 toward grazing, Yan 2018 Fig. 6; G = 1 of an unshadowed
// geometric lobe); an NDF whose disk sum is off 1 by more than 2%.
std::vector<std::string> image_warnings(const std::string& method, const LobeQuery& query, const LobeImage& image);

}  // namespace glintscope
