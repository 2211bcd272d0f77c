// Least-squares fits of parametric NDFs to NDF images (ndf_fit.hpp), with NLopt's BOBYQA
// (Powell 2009): a bound-constrained quadratic-model method that needs no derivatives, which
// suits five smooth parameters and an objective summed over tens of thousands of pixels.
#include "glintscope/fit/ndf_fit.hpp"

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "fit/ellipsoid_frame.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

// The image's pixels inside the disk: their normal and value.
struct DiskSamples {
    std::vector<Vec3> normals;
    std::vector<double> values;
    double pixel_area = 0.0;
};

DiskSamples disk_samples(const LobeImage& ndf) {
    DiskSamples samples;
    samples.pixel_area = disk_pixel_area(ndf.resolution);
    for (int row = 0; row < ndf.resolution; ++row)
        for (int col = 0; col < ndf.resolution; ++col) {
            const DiskPoint p = disk_pixel_point(row, col, ndf.resolution);
            if (!inside_unit_disk(p)) continue;
            samples.normals.push_back(direction_from_disk(p.x, p.y));
            samples.values.push_back(ndf.at(0, row, col));
        }
    return samples;
}

// A fixed chunk, so that the partial sums, added in order, do not depend on the thread count;
// large, because every evaluation starts its threads anew and one evaluation is cheap.
constexpr std::size_t chunk_size = 16384;

// Σ (D_model − D)² over the samples; partial sums per chunk added in chunk order.
double squared_error(const DiskSamples& samples, const NdfModel& model) {
    const std::size_t count = samples.values.size();
    std::vector<double> partial((count + chunk_size - 1) / chunk_size, 0.0);
    const EllipsoidFrame frame = ellipsoid_frame(model.parameters);
    parallel_for(count, chunk_size, [&](std::size_t begin, std::size_t end) {
        double sum = 0.0;
        for (std::size_t i = begin; i < end; ++i) {
            const Vec3 m = samples.normals[i];
            const double d = model.kind == NdfModelKind::ellipsoid ? ellipsoid_ndf(frame, m) : evaluate_ndf(model, m);
            sum += (d - samples.values[i]) * (d - samples.values[i]);
        }
        partial[begin / chunk_size] = sum;
    });
    double total = 0.0;
    for (double sum : partial) total += sum;
    return total;
}

double squared_norm(const DiskSamples& samples) {
    double total = 0.0;
    for (double v : samples.values) total += v * v;
    return total;
}

// D-weighted mean and covariance of the normals' disk points, with the principal axes.
struct Moments {
    Vec3 mean_normal;
    double major_angle = 0.0;  // of the major axis, from +x toward +y
    double major_variance = 0.0;
    double minor_variance = 0.0;
    double variance_x = 0.0;
    double variance_y = 0.0;
};

Moments moments(const DiskSamples& samples) {
    double w = 0.0, mx = 0.0, my = 0.0;
    for (std::size_t i = 0; i < samples.values.size(); ++i) {
        w += samples.values[i];
        mx += samples.values[i] * samples.normals[i].x;
        my += samples.values[i] * samples.normals[i].y;
    }
    if (!(w > 0.0)) throw Error("NDF image: no positive values inside the disk to fit");
    mx /= w, my /= w;
    double cxx = 0.0, cyy = 0.0, cxy = 0.0;
    for (std::size_t i = 0; i < samples.values.size(); ++i) {
        const double dx = samples.normals[i].x - mx, dy = samples.normals[i].y - my;
        cxx += samples.values[i] * dx * dx, cyy += samples.values[i] * dy * dy, cxy += samples.values[i] * dx * dy;
    }
    cxx /= w, cyy /= w, cxy /= w;
    const double half_trace = 0.5 * (cxx + cyy);
    const double spread = std::sqrt(0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy);
    return {direction_from_disk(mx, my), 0.5 * std::atan2(2.0 * cxy, cxx - cyy), half_trace + spread,
            std::max(half_trace - spread, 0.0), cxx, cyy};
}

constexpr double alpha_min = 1e-3;
constexpr double alpha_max = 4.0;

// For small α a normal's disk point is nearly its slope, whose variance is α²/2 for Beckmann.
double alpha_from_variance(double variance) { return std::clamp(std::sqrt(2.0 * variance), 2 * alpha_min, 1.0); }

// θ_x, θ_y that put the peak R^T n on `peak` for a given θ_z: R's third row is uᵀ R_z with
// u = (−cos θ_x sin θ_y, sin θ_x, cos θ_x cos θ_y) (Dong 2015 eq. 12), so u = R_z peak.
EllipsoidNdf tilt_towards(EllipsoidNdf ndf, Vec3 peak) {
    const double c = std::cos(ndf.theta_z), s = std::sin(ndf.theta_z);
    const Vec3 u{c * peak.x - s * peak.y, s * peak.x + c * peak.y, peak.z};
    ndf.theta_x = std::asin(std::clamp(u.y, -1.0, 1.0));
    ndf.theta_y = std::atan2(-u.x, u.z);
    return ndf;
}

NdfModel initial_model(const DiskSamples& samples, NdfModelKind kind) {
    const Moments m = moments(samples);
    NdfModel model{kind, {}};
    if (kind != NdfModelKind::ellipsoid) {
        model.parameters.alpha_x = alpha_from_variance(m.variance_x);
        model.parameters.alpha_y = alpha_from_variance(m.variance_y);
        return model;
    }
    model.parameters.alpha_x = alpha_from_variance(m.major_variance);
    model.parameters.alpha_y = alpha_from_variance(m.minor_variance);
    model.parameters.theta_z = -m.major_angle;  // the α_x axis lies along (cos θ_z, −sin θ_z)
    model.parameters = tilt_towards(model.parameters, m.mean_normal);
    return model;
}

// Solver variables: ln α_x, ln α_y (scale-free steps, α > 0), then θ_x, θ_y, θ_z.
std::vector<double> to_variables(const NdfModel& model) {
    const EllipsoidNdf& p = model.parameters;
    if (model.kind != NdfModelKind::ellipsoid) return {std::log(p.alpha_x), std::log(p.alpha_y)};
    return {std::log(p.alpha_x), std::log(p.alpha_y), p.theta_x, p.theta_y, p.theta_z};
}

NdfModel from_variables(NdfModelKind kind, const double* x) {
    NdfModel model{kind, {std::exp(x[0]), std::exp(x[1]), 0.0, 0.0, 0.0}};
    if (kind == NdfModelKind::ellipsoid) {
        model.parameters.theta_x = x[2];
        model.parameters.theta_y = x[3];
        model.parameters.theta_z = x[4];
    }
    return model;
}

struct Problem {
    const DiskSamples* samples;
    NdfModelKind kind;
    double norm;
    int evaluations = 0;
};

double objective(unsigned, const double* x, double*, void* data) {
    auto& problem = *static_cast<Problem*>(data);
    ++problem.evaluations;
    return squared_error(*problem.samples, from_variables(problem.kind, x)) / problem.norm;
}

using Optimizer = std::unique_ptr<std::remove_pointer_t<nlopt_opt>, decltype(&nlopt_destroy)>;

}  // namespace

std::string to_string(NdfModelKind kind) {
    switch (kind) {
        case NdfModelKind::ellipsoid: return "ellipsoid";
        case NdfModelKind::beckmann: return "beckmann";
        case NdfModelKind::ggx: return "ggx";
    }
    return "ellipsoid";
}

NdfModelKind parse_ndf_model_kind(const std::string& name) {
    for (NdfModelKind kind : {NdfModelKind::ellipsoid, NdfModelKind::beckmann, NdfModelKind::ggx})
        if (to_string(kind) == name) return kind;
    throw Error("--models: unknown model '" + name + "' (known: ellipsoid, beckmann, ggx)");
}

double evaluate_ndf(const NdfModel& model, Vec3 m) {
    const EllipsoidNdf& p = model.parameters;
    switch (model.kind) {
        case NdfModelKind::beckmann: return beckmann_ndf(p.alpha_x, p.alpha_y, m);
        case NdfModelKind::ggx: return ggx_ndf(p.alpha_x, p.alpha_y, m);
        case NdfModelKind::ellipsoid: break;
    }
    return ellipsoid_ndf(p, m);
}

LobeImage model_ndf_image(const NdfModel& model, int resolution) {
    if (resolution < 1) throw Error("resolution: must be at least 1, got " + std::to_string(resolution));
    LobeImage image = make_lobe_image(resolution, {0.5}, Quantity::ndf);
    const EllipsoidFrame frame = ellipsoid_frame(model.parameters);
    fill_by_direction(image, 0, 1, [&](DiskPoint p) {
        const Vec3 m = direction_from_disk(p.x, p.y);
        return model.kind == NdfModelKind::ellipsoid ? ellipsoid_ndf(frame, m) : evaluate_ndf(model, m);
    });
    image.metadata["ndf.model"] = to_string(model.kind);
    return image;
}

double ndf_relative_error(const LobeImage& ndf, const NdfModel& model) {
    const DiskSamples samples = disk_samples(ndf);
    return std::sqrt(squared_error(samples, model) / squared_norm(samples));
}

NdfFit fit_ndf(const LobeImage& ndf, NdfModelKind kind) {
    if (ndf.quantity != Quantity::ndf || ndf.resolution < 2 || ndf.layers() < 1)
        throw Error("NDF image: a fit needs an ndf image of at least 2x2 pixels");
    const DiskSamples samples = disk_samples(ndf);
    Problem problem{&samples, kind, squared_norm(samples)};
    std::vector<double> x = to_variables(initial_model(samples, kind));
    const auto n = static_cast<unsigned>(x.size());
    std::vector<double> lower(n), upper(n), step(n);
    for (unsigned i = 0; i < n; ++i) {
        const bool log_alpha = i < 2;
        lower[i] = log_alpha ? std::log(alpha_min) : -0.5 * pi;
        upper[i] = log_alpha ? std::log(alpha_max) : 0.5 * pi;
        step[i] = log_alpha ? 0.2 : 0.05;
    }
    if (kind == NdfModelKind::ellipsoid) lower[4] = x[4] - pi, upper[4] = x[4] + pi;  // θ_z: any turn
    Optimizer optimizer(nlopt_create(NLOPT_LN_BOBYQA, n), &nlopt_destroy);
    nlopt_set_min_objective(optimizer.get(), objective, &problem);
    nlopt_set_lower_bounds(optimizer.get(), lower.data());
    nlopt_set_upper_bounds(optimizer.get(), upper.data());
    nlopt_set_initial_step(optimizer.get(), step.data());
    nlopt_set_xtol_abs1(optimizer.get(), 1e-9);
    nlopt_set_ftol_rel(optimizer.get(), 1e-15);
    nlopt_set_maxeval(optimizer.get(), 4000);
    double minimum = 0.0;
    const nlopt_result result = nlopt_optimize(optimizer.get(), x.data(), &minimum);
    if (result < 0 && result != NLOPT_ROUNDOFF_LIMITED)
        throw Error("NDF fit: the solver failed (NLopt code " + std::to_string(int(result)) + ")");
    NdfModel model = from_variables(kind, x.data());
    model.parameters = canonical_ellipsoid(model.parameters);
    return {model, std::sqrt(std::max(minimum, 0.0)), problem.evaluations};
}

std::string ndf_fits_json(const std::vector<NdfFit>& fits, const std::string& source) {
    nlohmann::ordered_json report;
    report["source"] = source;
    report["weighting"] = "uniform over the projected disk: sum (D_model - D)^2 (2/N)^2";
    report["solver"] = "NLopt BOBYQA";
    report["fits"] = nlohmann::ordered_json::array();
    for (const NdfFit& fit : fits) {
        const EllipsoidNdf& p = fit.model.parameters;
        nlohmann::ordered_json entry;
        entry["model"] = to_string(fit.model.kind);
        entry["alpha_x"] = p.alpha_x;
        entry["alpha_y"] = p.alpha_y;
        if (fit.model.kind == NdfModelKind::ellipsoid) {
            entry["theta_x_deg"] = p.theta_x * 180.0 / pi;
            entry["theta_y_deg"] = p.theta_y * 180.0 / pi;
            entry["theta_z_deg"] = p.theta_z * 180.0 / pi;
        }
        entry["relative_error"] = fit.relative_error;
        entry["evaluations"] = fit.evaluations;
        report["fits"].push_back(entry);
    }
    return report.dump(2) + "\n";
}

}  // namespace glintscope
