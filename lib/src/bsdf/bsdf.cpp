// The BSDF and NDF contract over a method's lobe images (bsdf.hpp).
#include "glintscope/bsdf/bsdf.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <utility>

#include "numerics/disk_distribution.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "pipeline/method_table.hpp"

namespace glintscope {
namespace {

// A caller's direction as a unit vector; throws on one that names no direction.
Vec3 unit_direction(Vec3 omega, const char* name) {
    const double norm = length(omega);
    if (!std::isfinite(norm) || norm == 0.0) throw Error(std::string(name) + " is not a finite nonzero direction");
    return (1.0 / norm) * omega;
}

// The query a method's tables are computed for: one footprint, point-sampled pixels.
LobeQuery table_query(const std::string& method, const LobeQuery& query, Quantity quantity) {
    LobeQuery planned = query;
    planned.quantity = quantity;
    planned.supersample = 1;
    if (!planned.footprints.single())
        throw Error("a " + to_string(quantity) + " object describes one footprint, not an average over " +
                    to_string(planned.footprints));
    return plan_lobe(method, planned).query;
}

DiskDistribution image_distribution(const LobeImage& image) {
    return make_disk_distribution(image.resolution, image.layers(),
                                  std::vector<double>(image.values.begin(), image.values.end()));
}

const MethodEntry& method_entry(const std::string& method) {
    for (const MethodEntry& entry : method_table())
        if (entry.info.name == method) return entry;
    throw Error("unknown method '" + method + "'");  // plan_lobe has named the known ones before
}

// Whether the point field answers the planned (axis-aligned) footprint as the images do: a box of
// a method whose point query takes boxes on the texels' lattice is answered from its images, whose
// lattice follows the box's edges, so that eval is the image at pixel centres (the conformance
// suite's 1e-4; the point query differs by its triangles' steps, docs/geometric.md).
bool point_field_answers(const MethodEntry& entry, const Footprint& footprint) {
    return entry.point_field && !(entry.info.rotated_boxes && footprint.shape == FootprintShape::box);
}

// The method's own single-direction answers for the planned query's footprint, if it has any:
// its answers for one footprint, else its point field's at that footprint.
PointAnswers point_answers(const std::string& method, const LobeQuery& planned) {
    const MethodEntry& entry = method_entry(method);
    if (entry.point) return entry.point(planned);
    if (point_field_answers(entry, planned.footprint)) return entry.point_field(planned)(planned.footprint);
    return {};
}

// An NDF method's D(h) for the planned query's footprint from its point field, if it has one.
PointAnswers ndf_point_answers(const std::string& method, const LobeQuery& planned) {
    const MethodEntry& entry = method_entry(method);
    if (point_field_answers(entry, planned.footprint)) return entry.point_field(planned)(planned.footprint);
    return {};
}

// Errors of a method's own code come prefixed with its name.
template <typename Make>
auto prefixed(const std::string& method, const Make& make) {
    try {
        return make();
    } catch (const Error& e) {
        throw Error(method + ": " + e.what());
    }
}

}  // namespace

struct Bsdf::State {
    std::string method;
    // The planned query, shared with the field that made it (BsdfField::at makes one State per
    // shading point, which must not copy the query), and the footprint that replaces its own.
    std::shared_ptr<const LobeQuery> query;
    Footprint footprint;
    PointAnswers point;
    // The tables of the most recent ω_i, newest last, under the mutex; a table is immutable and
    // shared, so a reader keeps it while another thread replaces the list.
    static constexpr std::size_t kKeptTables = 16;
    std::mutex mutex;
    std::vector<std::pair<Vec3, std::shared_ptr<const DiskDistribution>>> recent;

    std::shared_ptr<const DiskDistribution> table(Vec3 omega_i) {
        {
            const std::lock_guard lock(mutex);
            for (const auto& [key, table] : recent)
                if (key.x == omega_i.x && key.y == omega_i.y && key.z == omega_i.z) return table;
        }
        // Computed outside the lock: two threads may both compute a new ω_i, with identical results.
        LobeQuery one = *query;
        one.footprint = footprint;
        one.omega_i = omega_i;
        auto made = std::make_shared<const DiskDistribution>(image_distribution(compute_lobe(method, one)));
        const std::lock_guard lock(mutex);
        recent.emplace_back(omega_i, made);
        if (recent.size() > kKeptTables) recent.erase(recent.begin());
        return made;
    }
};

Bsdf::Bsdf(std::shared_ptr<State> state) : state_(std::move(state)) {}

const std::string& Bsdf::method() const { return state_->method; }
const std::vector<double>& Bsdf::wavelengths_um() const { return state_->query->wavelengths_um; }

bool Bsdf::evaluates_directly() const { return static_cast<bool>(state_->point.eval); }
bool Bsdf::samples_directly() const { return static_cast<bool>(state_->point.sample); }
bool Bsdf::any_wavelength() const { return static_cast<bool>(state_->point.eval_at_wavelengths); }

std::vector<std::string> Bsdf::warnings() const {
    std::vector<std::string> warnings = footprint_warnings(state_->method, state_->footprint, state_->query->wavelengths_um);
    if (!state_->point.warning.empty()) warnings.push_back(state_->method + ": " + state_->point.warning);
    return warnings;
}

// Unit directions above the horizon from here on.
namespace {

std::vector<double> eval_above(const Bsdf::State& state, const std::shared_ptr<const DiskDistribution>& table,
                               Vec3 omega_i, Vec3 omega_o) {
    return state.point.eval ? state.point.eval(omega_i, omega_o) : values_at(*table, omega_o.x, omega_o.y);
}

}  // namespace

std::vector<double> Bsdf::eval(Vec3 omega_i, Vec3 omega_o) const {
    omega_i = unit_direction(omega_i, "omega_i");
    omega_o = unit_direction(omega_o, "omega_o");
    if (omega_i.z <= 0.0 || omega_o.z <= 0.0) return std::vector<double>(wavelengths_um().size(), 0.0);
    if (state_->point.eval) return state_->point.eval(omega_i, omega_o);
    return values_at(*state_->table(omega_i), omega_o.x, omega_o.y);
}

std::vector<double> Bsdf::eval_incident(const std::vector<Vec3>& omegas_i, Vec3 omega_o) const {
    const Vec3 unit_o = unit_direction(omega_o, "omega_o");
    std::vector<Vec3> units;
    units.reserve(omegas_i.size());
    for (const Vec3 omega_i : omegas_i) units.push_back(unit_direction(omega_i, "omega_i"));
    if (state_->point.eval_incident && unit_o.z > 0.0) return state_->point.eval_incident(units, unit_o);
    if (omegas_i.size() == 1) return eval(omegas_i[0], omega_o);  // a render's one light: its values as they are
    std::vector<double> values;
    values.reserve(omegas_i.size() * wavelengths_um().size());
    for (const Vec3 omega_i : omegas_i) {
        const std::vector<double> f = eval(omega_i, omega_o);
        values.insert(values.end(), f.begin(), f.end());
    }
    return values;
}

std::vector<double> Bsdf::eval(Vec3 omega_i, Vec3 omega_o, const std::vector<double>& chosen_um) const {
    for (const double lambda : chosen_um)
        if (!(lambda > 0.0 && std::isfinite(lambda)))
            throw Error("bsdf eval: wavelengths must be positive and finite (um), got " + shortest_text(lambda));
    if (state_->point.eval_at_wavelengths) {
        omega_i = unit_direction(omega_i, "omega_i");
        omega_o = unit_direction(omega_o, "omega_o");
        if (omega_i.z <= 0.0 || omega_o.z <= 0.0) return std::vector<double>(chosen_um.size(), 0.0);
        return state_->point.eval_at_wavelengths(omega_i, omega_o, chosen_um);
    }
    // Tables and images hold the query's wavelengths only: pick those asked for.
    const std::vector<double>& made_with = wavelengths_um();
    std::vector<std::size_t> layers;
    for (const double lambda : chosen_um) {
        const auto same = [lambda](double other) { return std::fabs(other - lambda) <= 1e-9 * lambda; };
        const auto found = std::find_if(made_with.begin(), made_with.end(), same);
        if (found == made_with.end())
            throw Error("bsdf eval: " + method() + " answers only the wavelengths its BSDF was made with (" +
                        join_numbers(made_with) + " um), not " + shortest_text(lambda) +
                        " um; make the BSDF with the wavelengths you need");
        layers.push_back(static_cast<std::size_t>(found - made_with.begin()));
    }
    const std::vector<double> all = eval(omega_i, omega_o);
    std::vector<double> picked;
    for (const std::size_t layer : layers) picked.push_back(all[layer]);
    return picked;
}

double Bsdf::pdf(Vec3 omega_i, Vec3 omega_o) const {
    omega_i = unit_direction(omega_i, "omega_i");
    omega_o = unit_direction(omega_o, "omega_o");
    if (omega_i.z <= 0.0 || omega_o.z <= 0.0) return 0.0;
    if (state_->point.pdf) return state_->point.pdf(omega_i, omega_o);
    // dA on the disk = cosθ_o dω_o.
    return disk_density(*state_->table(omega_i), omega_o.x, omega_o.y) * omega_o.z;
}

BsdfSample Bsdf::sample(Vec3 omega_i, double u1, double u2) const {
    omega_i = unit_direction(omega_i, "omega_i");
    BsdfSample result;
    result.weight.assign(wavelengths_um().size(), 0.0);
    if (omega_i.z <= 0.0) return result;
    std::shared_ptr<const DiskDistribution> table;
    std::vector<double> f;
    if (state_->point.sample) {
        EvaluatedSample s;
        if (state_->point.sample_with_f_r)
            s = state_->point.sample_with_f_r(omega_i, u1, u2);
        else
            s.sample = state_->point.sample(omega_i, u1, u2);
        if (!(s.sample.pdf > 0.0)) return result;
        result.omega_o = s.sample.direction;
        result.pdf = s.sample.pdf;
        f = std::move(s.f_r);
    } else {
        table = state_->table(omega_i);
        const auto point = sample_disk(*table, u1, u2);
        if (!point) return result;
        result.omega_o = direction_from_disk(point->x, point->y);
        result.pdf = disk_density(*table, point->x, point->y) * result.omega_o.z;  // dA = cosθ_o dω_o
    }
    if (f.empty()) f = eval_above(*state_, table, omega_i, result.omega_o);
    for (std::size_t k = 0; k < f.size(); ++k) result.weight[k] = f[k] * result.omega_o.z / result.pdf;
    return result;
}

std::vector<double> Bsdf::albedo(Vec3 omega_i) const {
    omega_i = unit_direction(omega_i, "omega_i");
    const std::size_t layers = wavelengths_um().size();
    if (omega_i.z <= 0.0) return std::vector<double>(layers, 0.0);
    if (!state_->point.eval) return state_->table(omega_i)->integral;
    if (state_->point.albedo) return state_->point.albedo(omega_i);
    // ∫ f_r dA over the disk by the images' own rule (image.hpp): K × K sub-pixels of the pixels
    // whose centre lies inside, so the albedo is the disk sum of the image at supersample K.
    const int n = state_->query->resolution, k = kAlbedoSupersample;
    std::vector<double> sum(layers, 0.0);
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            if (!inside_unit_disk(disk_pixel_point(row, col, n))) continue;
            for (int b = 0; b < k; ++b)
                for (int a = 0; a < k; ++a) {
                    const DiskPoint p = disk_subpixel_point(row, col, b, a, n, k);
                    if (!inside_unit_disk(p)) continue;
                    const std::vector<double> f = state_->point.eval(omega_i, direction_from_disk(p.x, p.y));
                    for (std::size_t l = 0; l < layers; ++l) sum[l] += f[l];
                }
        }
    const double cell_area = disk_pixel_area(n * k);
    for (double& s : sum) s *= cell_area;
    return sum;
}

Bsdf make_bsdf(const std::string& method, const LobeQuery& query) {
    auto state = std::make_shared<Bsdf::State>();
    state->method = method;
    state->query = std::make_shared<const LobeQuery>(table_query(method, query, Quantity::brdf));
    state->footprint = state->query->footprint;
    state->point = prefixed(method, [&] { return point_answers(method, *state->query); });
    return Bsdf(std::move(state));
}

struct BsdfField::State {
    std::string method;
    std::shared_ptr<const LobeQuery> query;  // planned; its footprint replaced by each `at`
    PointAnswersAt at;
    bool ellipses = false;
    bool rotated_boxes = false;
};

BsdfField::BsdfField(std::shared_ptr<const State> state) : state_(std::move(state)) {}

const std::string& BsdfField::method() const { return state_->method; }
const std::vector<double>& BsdfField::wavelengths_um() const { return state_->query->wavelengths_um; }
bool BsdfField::answers_ellipses() const { return state_->ellipses; }
bool BsdfField::answers_rotated_boxes() const { return state_->rotated_boxes; }

Bsdf BsdfField::at(const Footprint& footprint) const {
    auto state = std::make_shared<Bsdf::State>();
    state->method = state_->method;
    state->query = state_->query;
    validate(footprint);
    if (is_elliptical(footprint) && !state_->ellipses)
        throw Error(state_->method + " with these settings takes isotropic Gaussian footprints, not an ellipse");
    if (is_rotated_box(footprint) && !state_->rotated_boxes)
        throw Error(state_->method + " with these settings takes axis-aligned box footprints, not a box rotated by " +
                    shortest_text(footprint.axis_radians) + " rad");
    state->footprint = footprint;
    state->point = state_->at(footprint);
    return Bsdf(std::move(state));
}

std::vector<std::string> bsdf_field_methods() {
    std::vector<std::string> names;
    for (const MethodEntry& entry : method_table())
        if (entry.point_field) names.push_back(entry.info.name);
    return names;
}

BsdfField make_bsdf_field(const std::string& method, const LobeQuery& query) {
    auto state = std::make_shared<BsdfField::State>();
    state->method = method;
    state->query = std::make_shared<const LobeQuery>(table_query(method, query, Quantity::brdf));
    const MethodEntry& entry = method_entry(method);
    if (!entry.point_field) {
        const std::vector<std::string> names = bsdf_field_methods();
        throw Error(method + " has no point query for any footprint (a BSDF per shading point); methods that have one: " +
                    (names.empty() ? std::string("none") : join(names)));
    }
    state->at = prefixed(method, [&] { return entry.point_field(*state->query); });
    // Whether these settings answer a footprint the images cannot take by the point query.
    const auto answers = [&](const Footprint& probe) { return static_cast<bool>(state->at(probe).eval); };
    Footprint ellipse = state->query->footprint;
    ellipse.shape = FootprintShape::gaussian;
    ellipse.sigma_minor_um = 0.5 * ellipse.sigma_um;
    state->ellipses = entry.info.elliptical_footprints && answers(ellipse);
    Footprint rotated_box = state->query->footprint;
    rotated_box.shape = FootprintShape::box;
    rotated_box.size_um = rotated_box.size_y_um = 10.0;
    rotated_box.sigma_minor_um = 0.0;
    rotated_box.axis_radians = 0.5;
    state->rotated_boxes = entry.info.rotated_boxes && answers(rotated_box);
    return BsdfField(std::move(state));
}

struct Ndf::State {
    DiskDistribution table;  // D, sampling and pdf where the method has no point answers for them
    PointAnswers point;      // D(h) as point.eval(·, h); h and its pdf as point.sample, point.pdf
};

// What an NDF's point answers take as ω_i, which they do not use.
constexpr Vec3 kNdfFrameNormal{0.0, 0.0, 1.0};

Ndf::Ndf(std::shared_ptr<const State> state) : state_(std::move(state)) {}

std::vector<double> Ndf::eval(Vec3 h) const {
    h = unit_direction(h, "h");
    if (h.z <= 0.0) return std::vector<double>(state_->table.layers, 0.0);
    if (state_->point.eval) return state_->point.eval(kNdfFrameNormal, h);
    return values_at(state_->table, h.x, h.y);
}

bool Ndf::evaluates_directly() const { return static_cast<bool>(state_->point.eval); }
bool Ndf::samples_directly() const { return static_cast<bool>(state_->point.sample); }

double Ndf::pdf(Vec3 h) const {
    h = unit_direction(h, "h");
    if (h.z <= 0.0) return 0.0;
    if (state_->point.pdf) return state_->point.pdf(kNdfFrameNormal, h);
    return disk_density(state_->table, h.x, h.y) * h.z;
}

NdfSample Ndf::sample(double u1, double u2) const {
    if (state_->point.sample) {
        const DirectionSample s = state_->point.sample(kNdfFrameNormal, u1, u2);
        if (!(s.pdf > 0.0)) return {};
        return {s.direction, s.pdf};
    }
    const auto point = sample_disk(state_->table, u1, u2);
    if (!point) return {};
    const Vec3 h = direction_from_disk(point->x, point->y);
    return {h, disk_density(state_->table, point->x, point->y) * h.z};
}

std::vector<double> Ndf::normalisation() const { return state_->table.integral; }

Ndf make_ndf(const std::string& method, const LobeQuery& query) {
    const LobeQuery planned = table_query(method, query, Quantity::ndf);
    PointAnswers point;
    try {
        point = ndf_point_answers(method, planned);
    } catch (const Error& e) {
        throw Error(method + ": " + e.what());
    }
    return Ndf(std::make_shared<const Ndf::State>(
        Ndf::State{image_distribution(compute_lobe(method, planned)), std::move(point)}));
}

}  // namespace glintscope
