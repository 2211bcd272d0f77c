// The request pipeline: find the method, check and plan the query, run it over its footprints,
// label the image and collect what the caller should say.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/version.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/surface/square_texels.hpp"
#include "pipeline/method_table.hpp"

namespace glintscope {
namespace {

const MethodEntry& find_method(const std::string& name) {
    for (const MethodEntry& entry : method_table())
        if (entry.info.name == name) return entry;
    std::vector<std::string> known;
    for (const MethodEntry& entry : method_table()) known.push_back(entry.info.name);
    throw Error("unknown method '" + name + "' (available: " + join(known) + ")");
}

// The names of the methods for which `able` holds, for messages that point to an alternative.
template <typename Predicate>
std::string methods_that(Predicate able) {
    std::vector<std::string> names;
    for (const MethodEntry& entry : method_table())
        if (able(entry.info)) names.push_back(entry.info.name);
    return names.empty() ? "none" : join(names);
}

void check_quantity(const MethodInfo& method, Quantity quantity) {
    if (method.answers(quantity)) return;
    throw Error("method '" + method.name + "' does not compute " + to_string(quantity) + " (methods that do: " +
                methods_that([&](const MethodInfo& info) { return info.answers(quantity); }) + ")");
}

// The query keys (query_keys.hpp) in which a field is written.
std::vector<std::string> keys_of(QueryField field) {
    switch (field) {
        case QueryField::footprint: return {"footprint", "centre", "sigma_c", "box", "footprints"};
        case QueryField::incident: return {"omega_i"};
        case QueryField::wavelengths: return {"lambda"};
        case QueryField::model: return {"model"};
        case QueryField::material: return {"material"};
        case QueryField::supersample: return {"supersample"};
    }
    return {};
}

void label(LobeImage& image, const MethodInfo& method, const LobeQuery& query) {
    for (const auto& [key, value] : describe_query(query)) image.metadata.insert_or_assign(key, value);
    // A method may add fields it ignores for one quantity only (e.g. the incident direction of an NDF).
    std::vector<std::string> not_applicable;
    if (image.metadata.count("not_applicable")) not_applicable = split(image.metadata.at("not_applicable"), ',');
    for (QueryField field : method.ignored)
        for (const std::string& key : keys_of(field)) not_applicable.push_back(key);
    // Geometric optics without a material (F = 1): the wavelength changes nothing, so no caption
    // should state one.
    if (!method.wave_optics && query.material.name.empty() &&
        std::find(not_applicable.begin(), not_applicable.end(), "lambda") == not_applicable.end())
        not_applicable.push_back("lambda");
    if (!not_applicable.empty()) image.metadata["not_applicable"] = join(not_applicable);
    image.metadata["method"] = method.name;
    image.metadata["method.reference"] = method.reference;
    image.metadata["quantity"] = to_string(query.quantity);
    image.metadata["heightfield.tiling"] = query.field->periodic ? "periodic" : "non-periodic";
}

// One footprint through the method; errors prefixed with the method's name once (messages shared
// with a method's other entry points may already name it).
LobeImage compute_one(const MethodEntry& entry, const LobeQuery& query) {
    try {
        return entry.compute(query);
    } catch (const Error& e) {
        const std::string what = e.what();
        const std::string& name = entry.info.name;
        throw Error(what.starts_with(name + ": ") ? what : name + ": " + what);
    }
}

// One footprint, its progress reported per pass of the method's heavy loops (core/parallel.hpp).
LobeImage compute_single(const MethodEntry& entry, const LobeQuery& query, const RunProgress& progress) {
    if (!progress) return compute_one(entry, query);
    const ProgressScope scope([&](std::size_t, std::size_t done, std::size_t total) { progress(done, total); });
    return compute_one(entry, query);
}

// The mean of the method's images over the centres, pixel by pixel in order (deterministic).
LobeImage mean_over_centres(const MethodEntry& entry, const LobePlan& plan, const RunProgress& progress) {
    LobeImage mean;
    std::vector<double> sums;
    for (std::size_t k = 0; k < plan.centres.size(); ++k) {
        LobeQuery one = plan.query;
        one.footprint.centre_um = plan.centres[k];
        LobeImage image = compute_one(entry, one);
        if (sums.empty()) {
            mean = std::move(image);
            sums.assign(mean.values.begin(), mean.values.end());
        } else {
            for (std::size_t i = 0; i < sums.size(); ++i) sums[i] += image.values[i];
        }
        if (progress) progress(k + 1, plan.centres.size());
    }
    for (std::size_t i = 0; i < sums.size(); ++i) mean.values[i] = static_cast<float>(sums[i] / plan.centres.size());
    Point2 low{INFINITY, INFINITY}, high{-INFINITY, -INFINITY};
    for (const Point2& centre : plan.centres) {
        low = {std::min(low.x, centre.x), std::min(low.y, centre.y)};
        high = {std::max(high.x, centre.x), std::max(high.y, centre.y)};
    }
    mean.metadata["footprints.count"] = std::to_string(plan.centres.size());
    mean.metadata["footprints.centres_um"] = shortest_text(low.x) + "," + shortest_text(low.y) + " to " +
                                             shortest_text(high.x) + "," + shortest_text(high.y);
    return mean;
}

// The coherence window blurs a wave lobe by about λ/(2πσ_c) in disk units (the shortest
// wavelength's is the sharpest); a pixel is 2/N wide.
double coherence_blur(const LobeQuery& query) {
    const double lambda = *std::min_element(query.wavelengths_um.begin(), query.wavelengths_um.end());
    return lambda / (2.0 * pi * query.footprint.sigma_um);
}

bool point_sampled(const MethodInfo& method, const LobeQuery& query) {
    return method.wave_optics && query.footprint.shape == FootprintShape::gaussian &&
           coherence_blur(query) * query.supersample < 2.0 / query.resolution;
}

int supersample_for(const MethodInfo& method, const LobeQuery& query) {
    if (method.exact_pixels) return kExactPixels;
    if (!method.wave_optics || query.footprint.shape != FootprintShape::gaussian) return 1;
    const double pixel = 2.0 / query.resolution;
    return std::clamp(static_cast<int>(std::ceil(1.5 * pixel / coherence_blur(query))), 1, 8);
}

constexpr double kEnergyTolerance = 0.02;

// Σ f_r/F(ω_i·h) (2/N)² of one layer: the albedo the lobe would have with F = 1.
double reflected_fraction(const LobeQuery& query, const LobeImage& image, std::size_t layer) {
    if (query.material.name.empty()) return disk_sum(image, layer);
    const ComplexIndex eta = complex_refractive_index(query.material.name, image.wavelengths_um[layer]);
    const int n = image.resolution;
    double sum = 0.0;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const float value = image.at(layer, r, c);
            if (value == 0.0f) continue;
            const DiskPoint p = disk_pixel_point(r, c, n);
            const Vec3 h = normalize(query.omega_i + direction_from_disk(p.x, p.y));
            sum += value / fresnel_conductor(eta, dot(query.omega_i, h));
        }
    return sum * disk_pixel_area(n);
}

// Which term of the method creates energy beyond the material's reflectance.
std::string energy_source(const MethodInfo& method, const LobeQuery& query) {
    if (!method.wave_optics)
        return "a geometric model without shadowing and masking (G = 1) lets facets facing the light reflect more "
               "than their projected area (the geometric method's option shadowing=smith adds it)";
    switch (query.model) {
        case DiffractionModel::ohs:
        case DiffractionModel::ghs:
            return "the model's xi1 = cos(theta_o)/cos(theta_i) grows with the incidence (Yan 2018 Fig. 6); "
                   "--model kirchhoff keeps energy best";
        case DiffractionModel::rohs:
        case DiffractionModel::rghs:
            return "the model's xi1 = (cos theta_i + cos theta_o)^2/(4 cos theta_i cos theta_o) grows toward grazing "
                   "theta_o (Yan 2018 Fig. 6); --model kirchhoff keeps energy best";
        case DiffractionModel::kirchhoff:
            return "Kirchhoff's tangent-plane approximation ignores shadowing and masking, which matter at this "
                   "incidence or roughness";
    }
    return "";
}

std::string rounded(double value) { return shortest_text(std::round(value * 1e5) / 1e5); }

void check_footprint(const MethodInfo& method, const Footprint& footprint) {
    if (footprint.shape != FootprintShape::whole || method.whole_field) return;
    throw Error("method '" + method.name + "' needs a finite footprint, not the whole field (methods that take it: " +
                methods_that([](const MethodInfo& info) { return info.whole_field; }) + ")");
}

void check_option_keys(const MethodInfo& method, const LobeQuery& query) {
    for (const auto& option_value : query.method_options) {
        const std::string& key = option_value.first;  // a plain reference: lambdas may capture it
        const bool known = std::any_of(method.options.begin(), method.options.end(),
                                       [&](const MethodOption& option) { return option.key == key; });
        if (known) continue;
        std::vector<std::string> keys;
        for (const MethodOption& option : method.options) keys.push_back(option.key);
        throw Error("method '" + method.name + "' has no option '" + key + "' (options: " +
                    (keys.empty() ? "none" : join(keys)) + ")");
    }
}

// A method that reads square texels gets the field resampled along its coarser axis (never a
// silent change: the report, with its round-trip change, goes into the field's provenance, which
// the image's metadata carries as heightfield.square_texels, and into the run's notes).
void square_the_texels(LobePlan& plan) {
    Heightfield field = *plan.query.field;
    const SquareTexelReport report =
        make_texels_square(field, std::size_t{1} << 31, plan.method + " needs square texels, but");
    const std::string text = describe(report, field);
    field.provenance["square_texels"] = text + " (method " + plan.method + " needs square texels)";
    set_heightfield(plan.query, std::move(field));
    plan.notes.push_back("method " + plan.method + " needs square texels: " + text);
}

}  // namespace

std::vector<MethodInfo> lobe_methods() {
    std::vector<MethodInfo> infos;
    for (const MethodEntry& entry : method_table()) infos.push_back(entry.info);
    return infos;
}

MethodInfo lobe_method(const std::string& name) { return find_method(name).info; }

int recommended_supersample(const std::string& method, const LobeQuery& query) {
    return supersample_for(find_method(method).info, query);
}

LobePlan plan_lobe(const std::string& method, const LobeQuery& query) {
    const MethodEntry& entry = find_method(method);
    validate(query);
    check_quantity(entry.info, query.quantity);
    check_footprint(entry.info, query.footprint);
    try {
        check_option_keys(entry.info, query);
    } catch (const Error& e) {
        throw Error(method + ": " + e.what());
    }
    if (query.supersample == kExactPixels && !entry.info.exact_pixels)
        throw Error("method '" + method + "' cannot integrate pixels exactly (supersample exact; methods that can: " +
                    methods_that([](const MethodInfo& info) { return info.exact_pixels; }) + "): give K or auto");
    LobePlan plan{method, query, {}, {}};
    if (entry.info.needs_square_texels && !query.field->square_texels()) square_the_texels(plan);
    if (query.supersample == 0) {
        plan.query.supersample = supersample_for(entry.info, query);
        if (plan.query.supersample > 1)
            plan.notes.push_back("supersampled " + std::to_string(plan.query.supersample) + "x" +
                                 std::to_string(plan.query.supersample) +
                                 ", because the coherence blur lambda/(2 pi sigma_c) = " + rounded(coherence_blur(query)) +
                                 " is below a pixel (" + rounded(2.0 / query.resolution) +
                                 "; --supersample 1 point-samples)");
    }
    if (entry.info.ignores(QueryField::footprint) || query.footprint.shape == FootprintShape::whole) {
        plan.query.footprints = {};
        plan.centres = {query.footprint.centre_um};
        return plan;
    }
    plan.centres = footprint_centres(*query.field, query.footprint, query.footprints);
    for (const Point2& centre : plan.centres) {
        LobeQuery one = plan.query;
        one.footprint.centre_um = centre;
        check_footprint_inside(one);
    }
    if (plan.centres.size() > 1)
        plan.notes.push_back("averaged over " + std::to_string(plan.centres.size()) + " footprints (" +
                             to_string(query.footprints) + ")");
    return plan;
}

LobeRun run_lobe(const std::string& method, const LobeQuery& query, const RunProgress& progress) {
    const LobePlan plan = plan_lobe(method, query);
    const MethodEntry& entry = find_method(method);
    const auto start = std::chrono::steady_clock::now();
    LobeRun run;
    run.image = plan.query.footprints.single() ? compute_single(entry, plan.query, progress)
                                                : mean_over_centres(entry, plan, progress);
    run.image.quantity = plan.query.quantity;
    label(run.image, entry.info, plan.query);
    run.image.metadata["version"] = version();
    run.image.metadata["supersample.rule"] = query.supersample == 0 ? "auto" : "given";
    run.image.metadata["run.seconds"] = shortest_text(
        std::round(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() * 1e3) / 1e3);
    run.notes = plan.notes;
    // What a method chose on its own and wants said (e.g. the FFT's grid within the memory budget),
    // and what it found doubtful in its own answer ("METHOD.warning", e.g. gabor's kernel blur).
    for (const auto& [key, value] : run.image.metadata)
        if (key.starts_with("note.")) run.notes.push_back(value);
    run.warnings = query_warnings(method, plan.query);
    if (const auto own = run.image.metadata.find(method + ".warning"); own != run.image.metadata.end())
        run.warnings.push_back(method + ": " + own->second);
    for (std::string& warning : image_warnings(method, plan.query, run.image)) run.warnings.push_back(std::move(warning));
    return run;
}

LobeImage compute_lobe(const std::string& method, const LobeQuery& query) { return run_lobe(method, query).image; }

std::vector<std::string> query_warnings(const std::string& method, const LobeQuery& query) {
    const MethodInfo& info = find_method(method).info;
    std::vector<std::string> warnings;
    if (point_sampled(info, query)) {
        const double pixel = 2.0 / (query.resolution * query.supersample);
        warnings.push_back("the coherence blur lambda/(2 pi sigma_c) = " + rounded(coherence_blur(query)) +
                           " is smaller than a sub-pixel (" + rounded(pixel) +
                           "): the lobe is point-sampled and its albedo and peak are off (use --supersample " +
                           std::to_string(supersample_for(info, query) * query.supersample) +
                           " or a larger --res)");
    }
    for (std::string& warning : footprint_warnings(method, query.footprint, query.wavelengths_um))
        warnings.push_back(std::move(warning));
    // Kirchhoff-based models ignore shadowing and masking, which dominate near grazing.
    if (info.wave_optics && query.omega_i.z < std::cos(80.0 * pi / 180.0))
        warnings.push_back("incidence beyond 80 degrees: the diffraction models ignore shadowing and masking, "
                           "which dominate there: the lobe is outside their validity");
    return warnings;
}

std::vector<std::string> footprint_warnings(const std::string& method, const Footprint& f,
                                            const std::vector<double>& wavelengths_um) {
    std::vector<std::string> warnings;
    // A coherence footprint below the wavelength diffracts much of its light beyond the hemisphere
    // (its window's transform is wider than 1/λ), where the scalar models no longer describe it.
    if (find_method(method).info.wave_optics) {
        const double width =
            f.shape == FootprintShape::box ? std::min(box_width_um(f), box_height_um(f)) : minor_sigma_um(f);
        const double longest = *std::max_element(wavelengths_um.begin(), wavelengths_um.end());
        if (f.shape != FootprintShape::whole && width < longest)
            warnings.push_back(std::string(f.shape == FootprintShape::box ? "the box side " : "sigma_c ") +
                               shortest_text(width) + " um is below the wavelength " + shortest_text(longest) +
                               " um: the footprint's own diffraction sends much of the light beyond the hemisphere, "
                               "where the scalar diffraction models no longer hold");
    }
    return warnings;
}

std::vector<std::string> image_warnings(const std::string& method, const LobeQuery& query, const LobeImage& image) {
    std::vector<std::string> warnings;
    for (std::size_t layer = 0; layer < image.layers(); ++layer) {
        const double sum = disk_sum(image, layer);
        const double lambda = image.wavelengths_um[layer];
        const std::string at = "at " + shortest_text(lambda) + " um";
        if (image.quantity == Quantity::brdf) {
            // The albedo with the material's Fresnel factor F(ω_i·h) taken out of every pixel (the
            // methods apply it so): above 1, the method or model creates energy.
            const double unit = reflected_fraction(query, image, layer);
            if (unit > 1.0 + kEnergyTolerance) {
                warnings.push_back("albedo " + shortest_text(std::round(sum * 1e4) / 1e4) + " " + at +
                                   (query.material.name.empty()
                                        ? std::string(" exceeds 1")
                                        : " is " + shortest_text(std::round(unit * 1e4) / 1e4) + " of what " +
                                              query.material.name + "'s Fresnel reflectance lets through") +
                                   ", more than 2% over: " + energy_source(lobe_method(method), query));
                break;
            }
        }
        if (image.quantity == Quantity::ndf && std::fabs(sum - 1.0) > kEnergyTolerance) {
            warnings.push_back("the NDF integrates to " + shortest_text(std::round(sum * 1e4) / 1e4) +
                               " on the disk, not 1 (mass beyond the disk or the footprint, or peaks narrower "
                               "than a pixel that its centres miss: try --supersample)");
            break;
        }
    }
    return warnings;
}

}  // namespace glintscope
