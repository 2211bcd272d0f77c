// A lit patch through a pinhole camera (render.hpp): camera rays, shading points and the sum over
// lights, with every f_r from the method's BsdfField.
#include "glintscope/render/render.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"
#include "glintscope/lobe/query_keys.hpp"

namespace glintscope {
namespace {

constexpr int kMaxSide = 16384;
constexpr long long kMaxPixels = 1LL << 26;
constexpr int kMaxSamplesPerPixel = 256;
constexpr double kSquareMetresPerSquareMicrometre = 1e-12;

bool finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string text(Vec3 v) { return shortest_text(v.x) + "," + shortest_text(v.y) + "," + shortest_text(v.z); }

int samples_per_axis(int samples_per_pixel) { return int(std::lround(std::sqrt(double(samples_per_pixel)))); }

void validate_camera(const PinholeCamera& camera) {
    if (!finite(camera.position_um) || !finite(camera.look_at_um))
        throw Error("camera position and look-at must be finite, got " + text(camera.position_um) + " : " +
                    text(camera.look_at_um));
    if (!(camera.position_um.z > 0.0))
        throw Error("the camera must be above the patch (z > 0), got z = " + shortest_text(camera.position_um.z) + " um");
    if (length(camera.look_at_um - camera.position_um) == 0.0) throw Error("the camera looks at its own position");
    if (!(camera.vertical_fov_degrees > 0.0 && camera.vertical_fov_degrees < 180.0))
        throw Error("field of view must be between 0 and 180 degrees, got " + shortest_text(camera.vertical_fov_degrees));
    if (camera.width < 1 || camera.height < 1 || camera.width > kMaxSide || camera.height > kMaxSide ||
        (long long)camera.width * camera.height > kMaxPixels)
        throw Error("image size " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                    " is outside 1.." + std::to_string(kMaxSide) + " per side and " + std::to_string(kMaxPixels) +
                    " pixels");
}

void validate_lights(const std::vector<PointLight>& lights) {
    if (lights.empty()) throw Error("a render needs at least one light");
    for (std::size_t k = 0; k < lights.size(); ++k) {
        const PointLight& light = lights[k];
        const std::string name = "light " + std::to_string(k + 1);
        if (!finite(light.position_um)) throw Error(name + " position must be finite, got " + text(light.position_um));
        if (!(light.position_um.z > 0.0))
            throw Error(name + " is below the patch's horizon (z <= 0), got z = " + shortest_text(light.position_um.z) + " um");
        if (!(light.intensity_w_per_sr >= 0.0 && std::isfinite(light.intensity_w_per_sr)))
            throw Error(name + " intensity must be finite and nonnegative, got " + shortest_text(light.intensity_w_per_sr));
    }
}

// The camera's orthonormal frame: up is the world +z projected (+y when looking straight down).
struct CameraFrame {
    Vec3 origin, forward, right, up;
    double tan_half_height = 0.0;
    double tan_half_width = 0.0;
};

CameraFrame camera_frame(const PinholeCamera& camera) {
    CameraFrame frame;
    frame.origin = camera.position_um;
    frame.forward = normalize(camera.look_at_um - camera.position_um);
    Vec3 world_up{0.0, 0.0, 1.0};
    if (length(cross(frame.forward, world_up)) < 1e-9) world_up = {0.0, 1.0, 0.0};
    frame.right = normalize(cross(frame.forward, world_up));
    frame.up = cross(frame.right, frame.forward);
    frame.tan_half_height = std::tan(0.5 * camera.vertical_fov_degrees * pi / 180.0);
    frame.tan_half_width = frame.tan_half_height * camera.width / camera.height;
    return frame;
}

// The ray through image point p (pixels), unnormalised: forward + s_x right + s_y up, s on the
// image plane at distance 1.
Vec3 image_direction(const CameraFrame& frame, int width, int height, Point2 p) {
    const double sx = (2.0 * p.x / width - 1.0) * frame.tan_half_width;
    const double sy = (1.0 - 2.0 * p.y / height) * frame.tan_half_height;
    return frame.forward + sx * frame.right + sy * frame.up;
}

// A pixel's side on the image plane at distance 1 (square pixels).
double pixel_side(const CameraFrame& frame, int height) { return 2.0 * frame.tan_half_height / height; }

// The Gaussian of a square of `side` (image-plane units) about the ray `direction` on z = 0: the
// hit x = o + t d, t = −o_z/d_z, moves with the image-plane point s by
// ∂x/∂s = t (∂d/∂s − (∂d_z/∂s / d_z) d), ∂d/∂s = right or up; the box's covariance side²/12 per
// axis carried through these columns of J, then its principal axes.
SurfaceFootprint footprint_on_plane(const CameraFrame& frame, Vec3 direction, double side) {
    const double t = -frame.origin.z / direction.z;
    const auto column = [&](Vec3 along) { return (side * t) * (along - (along.z / direction.z) * direction); };
    const Vec3 a = column(frame.right), b = column(frame.up);
    const double xx = (a.x * a.x + b.x * b.x) / 12.0, yy = (a.y * a.y + b.y * b.y) / 12.0;
    const double xy = (a.x * a.y + b.x * b.y) / 12.0;
    // Eigenvalues mean ± spread; the major eigenvector's angle ½ atan2(2 xy, xx − yy).
    const double mean = 0.5 * (xx + yy), spread = std::hypot(0.5 * (xx - yy), xy);
    return {std::sqrt(mean + spread), std::sqrt(std::max(0.0, mean - spread)), 0.5 * std::atan2(2.0 * xy, xx - yy)};
}

// x modulo period, in [0, period).
double wrap(double x, double period) {
    const double r = std::fmod(x, period);
    return r < 0.0 ? r + period : r;
}

struct SceneGeometry {
    CameraFrame frame;
    int width = 0, height = 0, per_axis = 1;
    double half_patch = 0.0;
    double period_x = 0.0, period_y = 0.0;

    SceneGeometry(const Scene& scene, const RenderSettings& settings)
        : frame(camera_frame(scene.camera)),
          width(scene.camera.width),
          height(scene.camera.height),
          per_axis(samples_per_axis(settings.samples_per_pixel)),
          half_patch(0.5 * scene.patch_um),
          period_x(scene.query.field->cols * scene.query.field->texel_um),
          period_y(scene.query.field->height_um()) {}

    // Sub-pixel (a, b) of pixel (row, col): at ((col + (a + ½)/n), (row + (b + ½)/n)) in pixel units.
    ShadingPoint at(int row, int col, int b, int a) const {
        const Point2 image_point{col + (a + 0.5) / per_axis, row + (b + 0.5) / per_axis};
        const Vec3 direction = image_direction(frame, width, height, image_point);
        ShadingPoint point;
        if (!(direction.z < 0.0)) return point;
        const Vec3 x = frame.origin + (-frame.origin.z / direction.z) * direction;
        if (std::fabs(x.x) > half_patch || std::fabs(x.y) > half_patch) return point;
        point.hit = true;
        point.position_um = {x.x, x.y, 0.0};
        point.heightfield_um = {wrap(x.x + half_patch, period_x), wrap(x.y + half_patch, period_y)};
        point.omega_o = normalize(frame.origin - point.position_um);
        point.cell = footprint_on_plane(frame, direction, pixel_side(frame, height) / per_axis);
        return point;
    }
};

std::string lights_text(const std::vector<PointLight>& lights) {
    std::vector<std::string> parts;
    for (const PointLight& light : lights) parts.push_back(text(light.position_um) + ":" + shortest_text(light.intensity_w_per_sr));
    return join(parts, ";");
}

// Which footprint a shading point's BSDF is made for (shading_footprint).
enum class PixelFootprint { none, equal_area, ellipse, rectangle };

PixelFootprint pixel_footprint_of(const Scene& scene, const BsdfField& field) {
    if (!renders_pixel_footprint(scene.method)) return PixelFootprint::none;
    if (field.answers_rotated_boxes()) return PixelFootprint::rectangle;
    return field.answers_ellipses() ? PixelFootprint::ellipse : PixelFootprint::equal_area;
}

Provenance render_metadata(const Scene& scene, const RenderSettings& settings, PixelFootprint pixel) {
    Provenance metadata = describe_query(scene.query);
    metadata["method"] = scene.method;
    metadata["method.reference"] = lobe_method(scene.method).reference;
    metadata["render.patch_um"] = shortest_text(scene.patch_um);
    metadata["render.camera_um"] = text(scene.camera.position_um) + ":" + text(scene.camera.look_at_um);
    metadata["render.fov_degrees"] = shortest_text(scene.camera.vertical_fov_degrees);
    metadata["render.size"] = std::to_string(scene.camera.width) + "x" + std::to_string(scene.camera.height);
    metadata["render.lights_um_w_per_sr"] = lights_text(scene.lights);
    metadata["render.light_spectrum"] = to_string(scene.light_spectrum);
    metadata["render.spp"] = std::to_string(settings.samples_per_pixel);
    metadata["render.footprint"] =
        pixel == PixelFootprint::rectangle    ? "pixel: each shading point's cell on the patch, as the rectangle of its covariance "
                                                "(sides sqrt(12) major x sqrt(12) minor along its axis; sigma_c recorded per "
                                                "query is not used)"
        : pixel == PixelFootprint::ellipse    ? "pixel: each shading point's cell on the patch, as its elliptical Gaussian "
                                                "(sigma_c recorded per query is not used)"
        : pixel == PixelFootprint::equal_area ? "pixel: each shading point's cell on the patch, as the isotropic Gaussian of "
                                                "its area (sigma_c recorded per query is not used)"
                                              : "coherence: the query's footprint centred at each shading point";
    metadata["render.units"] = "radiance W m^-2 sr^-1 per wavelength (direct light from point lights)";
    return metadata;
}

}  // namespace

void validate_view(const Scene& scene, const RenderSettings& settings) {
    validate_camera(scene.camera);
    validate_lights(scene.lights);
    if (!(scene.patch_um > 0.0 && std::isfinite(scene.patch_um)))
        throw Error("patch size must be positive and finite, got " + shortest_text(scene.patch_um) + " um");
    const int n = samples_per_axis(settings.samples_per_pixel);
    if (settings.samples_per_pixel < 1 || settings.samples_per_pixel > kMaxSamplesPerPixel ||
        n * n != settings.samples_per_pixel)
        throw Error("spp must be a square number from 1 to " + std::to_string(kMaxSamplesPerPixel) +
                    " (n x n points on a regular sub-pixel grid), got " + std::to_string(settings.samples_per_pixel));
    if (settings.threads < 0) throw Error("threads must be 0 (automatic) or more, got " + std::to_string(settings.threads));
    const std::vector<std::string> methods = bsdf_field_methods();
    if (std::find(methods.begin(), methods.end(), scene.method) == methods.end()) {
        lobe_method(scene.method);  // an unknown name is refused with the list of methods
        throw Error("method " + scene.method + " cannot answer a BSDF per shading point; methods that can: " +
                    (methods.empty() ? std::string("none") : join(methods)));
    }
}

void validate(const Scene& scene, const RenderSettings& settings) {
    validate_view(scene, settings);
    if (!scene.query.field) throw Error("a render needs a heightfield");
    if (!scene.query.field->periodic)
        throw Error("the patch tiles the heightfield, which is not periodic: its seams would show (load it as periodic, "
                    "or prepare a periodic crop)");
    if (renders_pixel_footprint(scene.method) && scene.query.footprint.shape != FootprintShape::gaussian)
        throw Error("a " + scene.method + " render sees each pixel's cell on the patch, not the query's box or the "
                    "whole field");
    LobeQuery query = scene.query;
    query.quantity = Quantity::brdf;
    query.supersample = 1;
    plan_lobe(scene.method, query);
}

std::vector<ShadingPoint> shading_points(const Scene& scene, const RenderSettings& settings, int row, int col) {
    const SceneGeometry geometry(scene, settings);
    std::vector<ShadingPoint> points;
    for (int b = 0; b < geometry.per_axis; ++b)
        for (int a = 0; a < geometry.per_axis; ++a) points.push_back(geometry.at(row, col, b, a));
    return points;
}

double SurfaceFootprint::equal_area_sigma_um() const { return std::sqrt(major_um * minor_um); }

SurfaceFootprint image_footprint(const PinholeCamera& camera, Point2 image_point, double side_pixels) {
    const CameraFrame frame = camera_frame(camera);
    const Vec3 direction = image_direction(frame, camera.width, camera.height, image_point);
    if (!(direction.z < 0.0) || !(camera.position_um.z > 0.0))
        throw Error("image point " + shortest_text(image_point.x) + "," + shortest_text(image_point.y) +
                    " does not see the patch's plane");
    return footprint_on_plane(frame, direction, side_pixels * pixel_side(frame, camera.height));
}

bool renders_pixel_footprint(const std::string& method) { return !lobe_method(method).wave_optics; }

namespace {

Footprint footprint_at(const Scene& scene, const ShadingPoint& point, PixelFootprint pixel) {
    Footprint footprint = scene.query.footprint;
    footprint.centre_um = point.heightfield_um;
    if (pixel == PixelFootprint::none) return footprint;
    if (pixel == PixelFootprint::rectangle) {
        // The cell itself, as the rectangle of its covariance (a side a has variance a²/12): sides
        // √12 major × √12 minor along its axis, area 12 major minor, the cell's on the patch, so
        // that neighbouring cells hardly overlap and each texel is tested about once.
        footprint.shape = FootprintShape::box;
        footprint.size_um = std::sqrt(12.0) * point.cell.major_um;
        footprint.size_y_um = std::sqrt(12.0) * point.cell.minor_um;
        footprint.sigma_minor_um = 0.0;
        footprint.axis_radians = point.cell.axis_radians;
        return footprint;
    }
    // The weight |w|²/A_c has covariance Σ_c/2 (conventions.md): σ_c = √2 σ of the cell's Gaussian.
    footprint.shape = FootprintShape::gaussian;
    if (pixel == PixelFootprint::ellipse && point.cell.minor_um < point.cell.major_um) {
        footprint.sigma_um = std::sqrt(2.0) * point.cell.major_um;
        footprint.sigma_minor_um = std::sqrt(2.0) * point.cell.minor_um;
        footprint.axis_radians = point.cell.axis_radians;
    } else {
        footprint.sigma_um = std::sqrt(2.0) * point.cell.equal_area_sigma_um();
    }
    return footprint;
}

}  // namespace

Footprint shading_footprint(const Scene& scene, const ShadingPoint& point, const BsdfField& field) {
    return footprint_at(scene, point, pixel_footprint_of(scene, field));
}

LightArrival light_arrival(const PointLight& light, Vec3 position_um) {
    const Vec3 to_light = light.position_um - position_um;
    const double r2 = dot(to_light, to_light);
    LightArrival arrival;
    arrival.omega_i = (1.0 / std::sqrt(r2)) * to_light;
    arrival.irradiance = light.intensity_w_per_sr * arrival.omega_i.z / (r2 * kSquareMetresPerSquareMicrometre);
    return arrival;
}

namespace {

// text split once at `separator` into two nonempty parts.
std::pair<std::string, std::string> split_pair(const std::string& text, char separator, const std::string& form) {
    const auto at = text.find(separator);
    if (at == std::string::npos || at == 0 || at + 1 == text.size() || text.find(separator, at + 1) != std::string::npos)
        throw Error("'" + text + "' is not of the form " + form);
    return {text.substr(0, at), text.substr(at + 1)};
}

}  // namespace

Vec3 parse_position_um(const std::string& text) {
    const std::vector<std::string> parts = split(text, ',');
    if (parts.size() != 3) throw Error("'" + text + "' is not a position X,Y,Z (lengths, e.g. 0,-7cm,7cm)");
    try {
        return {parse_length_um(parts[0]), parse_length_um(parts[1]), parse_length_um(parts[2])};
    } catch (const Error& e) {
        throw Error("position '" + text + "': " + e.what());
    }
}

void parse_camera(const std::string& text, PinholeCamera& camera) {
    const auto [position, look_at] = split_pair(text, ':', "X,Y,Z:LX,LY,LZ (camera position : look-at point)");
    camera.position_um = parse_position_um(position);
    camera.look_at_um = parse_position_um(look_at);
}

PointLight parse_light(const std::string& text) {
    const auto [position, intensity] = split_pair(text, ':', "X,Y,Z:I (light position : intensity in W/sr)");
    PointLight light;
    light.position_um = parse_position_um(position);
    try {
        light.intensity_w_per_sr = parse_number(intensity);
    } catch (const Error&) {
        throw Error("light '" + text + "': intensity '" + intensity + "' is not a number (W/sr)");
    }
    return light;
}

void parse_image_size(const std::string& text, PinholeCamera& camera) {
    const auto [width, height] = split_pair(text, 'x', "WIDTHxHEIGHT (e.g. 1280x720)");
    const auto whole = [&](const std::string& part) {
        double value = -1.0;
        try {
            value = parse_number(part);
        } catch (const Error&) {
        }
        if (value != std::floor(value) || value < 1.0 || value > 1e9)
            throw Error("image size '" + text + "' must be WIDTHxHEIGHT in whole pixels");
        return int(value);
    };
    camera.width = whole(width);
    camera.height = whole(height);
}

std::vector<Scene> light_sweep(const Scene& scene, int frames, double span_um) {
    if (frames < 2 || frames > 256) throw Error("a light sweep needs 2 to 256 frames, got " + std::to_string(frames));
    if (!(span_um > 0.0) || !std::isfinite(span_um))
        throw Error("the light sweep's span must be a positive length, got " + shortest_text(span_um) + " um");
    validate_camera(scene.camera);
    const Vec3 right = camera_frame(scene.camera).right;
    std::vector<Scene> sweep;
    for (int k = 0; k < frames; ++k) {
        Scene frame = scene;
        const double offset = (double(k) / (frames - 1) - 0.5) * span_um;
        for (PointLight& light : frame.lights) light.position_um = light.position_um + offset * right;
        validate_lights(frame.lights);
        sweep.push_back(std::move(frame));
    }
    return sweep;
}

namespace {

// The method's BSDF for any footprint of the scene's heightfield: built once per query.
BsdfField scene_field(const Scene& scene) {
    LobeQuery query = scene.query;
    query.quantity = Quantity::brdf;
    query.supersample = 1;
    return make_bsdf_field(scene.method, query);
}

RenderImage empty_image(const Scene& scene, const BsdfField& field, const RenderSettings& settings) {
    RenderImage image;
    image.width = scene.camera.width;
    image.height = scene.camera.height;
    image.wavelengths_um = field.wavelengths_um();
    image.values.assign(image.pixels() * image.wavelengths_um.size(), 0.0f);
    image.metadata = render_metadata(scene, settings, pixel_footprint_of(scene, field));
    // A wave method weighs every shading point with the same coherence footprint, so its BSDF's
    // warnings (e.g. gabor's kernel blur) hold for the whole image.
    if (!renders_pixel_footprint(scene.method)) image.warnings = field.at(scene.query.footprint).warnings();
    return image;
}

// The frames' images (scenes that differ only in their lights): each shading point's BSDF is made
// once and evaluated for all frames' lights in one eval_incident call (gabor: one walk of the
// footprint's kernels for all of them; docs/render.md), each frame's pixel summed in the same
// order as a render of that frame alone.
std::vector<RenderImage> render_frames(const std::vector<Scene>& frames, const BsdfField& field,
                                       const RenderSettings& settings, const RunProgress& progress) {
    const Scene& scene = frames.front();
    const SceneGeometry geometry(scene, settings);
    const std::size_t layers = field.wavelengths_um().size();
    std::vector<RenderImage> images;
    for (const Scene& frame : frames) images.push_back(empty_image(frame, field, settings));

    const int width = geometry.width, height = geometry.height;
    const int spp = settings.samples_per_pixel;
    const PixelFootprint pixel_footprint = pixel_footprint_of(scene, field);
    std::atomic<std::size_t> rows_done{0};
    std::mutex progress_mutex;
    parallel_for(std::size_t(height), 1, [&](std::size_t begin, std::size_t end) {
        std::vector<double> sums(frames.size() * layers);  // frame-major: the pixel's sum per frame and layer
        // A shading point's lit arrivals over all frames, in frame then light order.
        std::vector<Vec3> omegas_i;
        std::vector<double> irradiances;
        std::vector<std::size_t> arrival_frames;
        for (int row = int(begin); row < int(end); ++row) {
            for (int col = 0; col < width; ++col) {
                std::fill(sums.begin(), sums.end(), 0.0);
                for (int b = 0; b < geometry.per_axis; ++b)
                    for (int a = 0; a < geometry.per_axis; ++a) {
                        const ShadingPoint point = geometry.at(row, col, b, a);
                        if (!point.hit) continue;
                        const Bsdf bsdf = field.at(footprint_at(scene, point, pixel_footprint));
                        omegas_i.clear();
                        irradiances.clear();
                        arrival_frames.clear();
                        for (std::size_t frame = 0; frame < frames.size(); ++frame)
                            for (const PointLight& light : frames[frame].lights) {
                                const LightArrival arrival = light_arrival(light, point.position_um);
                                if (arrival.irradiance == 0.0) continue;
                                omegas_i.push_back(arrival.omega_i);
                                irradiances.push_back(arrival.irradiance);
                                arrival_frames.push_back(frame);
                            }
                        if (omegas_i.empty()) continue;
                        const std::vector<double> f = bsdf.eval_incident(omegas_i, point.omega_o);
                        for (std::size_t n = 0; n < omegas_i.size(); ++n) {
                            double* sum = &sums[arrival_frames[n] * layers];
                            for (std::size_t k = 0; k < layers; ++k)
                                sum[k] += f[n * layers + k] * irradiances[n];  // L = f_r E
                        }
                    }
                for (std::size_t frame = 0; frame < frames.size(); ++frame)
                    for (std::size_t k = 0; k < layers; ++k)
                        images[frame].values[(k * height + row) * std::size_t(width) + col] =
                            float(sums[frame * layers + k] / spp);
            }
            const std::size_t done = ++rows_done;
            if (progress) {
                const std::lock_guard lock(progress_mutex);
                progress(done, std::size_t(height));
            }
        }
    });
    return images;
}

// The render's thread count: settings.threads, or with 0 the caller's (its own ThreadScope, such
// as the CLI's --threads), which a scope of 0 would replace by the default.
int render_threads(const RenderSettings& settings) { return settings.threads > 0 ? settings.threads : thread_count(); }

}  // namespace

RenderImage render(const Scene& scene, const RenderSettings& settings, const RunProgress& progress) {
    validate(scene, settings);
    const ThreadScope threads(render_threads(settings));  // the field's hierarchy and the rows
    return std::move(render_frames({scene}, scene_field(scene), settings, progress).front());
}

std::vector<RenderImage> render_light_sweep(const Scene& scene, int frames, double span_um, const RenderSettings& settings,
                                            const RunProgress& progress) {
    const std::vector<Scene> sweep = light_sweep(scene, frames, span_um);
    validate(scene, settings);
    const ThreadScope threads(render_threads(settings));
    return render_frames(sweep, scene_field(scene), settings, progress);  // the lights move; the surface does not
}

}  // namespace glintscope
