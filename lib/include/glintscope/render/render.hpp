#pragma once
// A lit patch of the surface seen through a pinhole camera (Yan 2018 §6.2 "Patch", Fig. 12):
// the heightfield tiled over the plane z = 0, point lights, direct lighting only. Each pixel
// averages the radiance of spp shading points on a regular sub-pixel grid (Yan 2018 §5: 4 to
// 25), each the method's BSDF for a footprint centred there (Yan 2018 §3.1: coherent within a
// coherence area, incoherently averaged over the pixel):
//   L(x, ω_o) = Σ_lights f_r(ω_i, ω_o; footprint at x) cosθ_i I / r²   [W m⁻² sr⁻¹]
// f_r comes from the BSDF contract (bsdf.hpp, BsdfField::at): the renderer adds no physics.
//
// World frame: lengths in µm, the patch is the square |x|, |y| ≤ patch/2 of the plane z = 0 with
// +z its mean normal, and its x, y axes are the heightfield's; the heightfield's origin lies at
// the patch's corner (−patch/2, −patch/2) and repeats with its period (cols·dx, rows·dx). Camera
// rays that miss the patch see black. Image rows run down the camera's up vector, row 0 at the
// top; columns run along its right vector (up is the world +z projected, right = forward × up).
#include <cstddef>
#include <string>
#include <vector>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/optics/spectrum.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/surface/metadata.hpp"

namespace glintscope {

struct PinholeCamera {
    Vec3 position_um{0.0, -70710.678118654752, 70710.678118654752};  // 10 cm away, 45° elevation
    Vec3 look_at_um{0.0, 0.0, 0.0};
    double vertical_fov_degrees = 30.0;
    int width = 1280;
    int height = 720;
};

struct PointLight {
    Vec3 position_um{0.0, 70710.678118654752, 70710.678118654752};  // opposite the default camera
    double intensity_w_per_sr = 1.0;  // radiant intensity at every wavelength of the query
};

struct Scene {
    double patch_um = 50000.0;  // side of the square patch (Yan 2018: 5 cm)
    PinholeCamera camera;
    std::vector<PointLight> lights{PointLight{}};
    // The lights' spectrum: the colour pipeline's illuminant (colour.hpp), by which a spectral
    // render's per-wavelength radiance is weighted into XYZ. All lights share it.
    Illuminant light_spectrum = Illuminant::d65;
    std::string method = "gabor";
    // Per shading point: the heightfield, wavelengths, diffraction model, material, coherence
    // footprint (σ_c or a box; its centre is the shading point's) and method options.
    LobeQuery query;
};

struct RenderSettings {
    int samples_per_pixel = 4;  // spp: a square number, n × n points at the sub-pixel centres
    int threads = 0;            // 0: the caller's thread_count()
};

// Radiance in W m⁻² sr⁻¹ per wavelength of the query.
struct RenderImage {
    int width = 0;
    int height = 0;
    std::vector<double> wavelengths_um;
    std::vector<float> values;  // [layer][row][col]
    Provenance metadata;        // the query (query_keys.hpp), "render.*" (scene, spp) and the method
    // Physics warnings that hold for every pixel, one line each: a wave method's BSDF warnings at
    // the coherence footprint (Bsdf::warnings; every shading point weighs with it).
    std::vector<std::string> warnings;

    std::size_t pixels() const { return std::size_t(width) * height; }
    float at(std::size_t layer, int row, int col) const { return values[(layer * height + row) * std::size_t(width) + col]; }
};

// Checks everything a render needs before any work: a camera above the patch with a finite
// look-at elsewhere, a field of view in (0°, 180°), a size up to 16384 per side and 2^26 pixels,
// lights above the patch with finite nonnegative intensities, a positive patch, a square spp of
// 1 to 256, a periodic heightfield (it is tiled) and a query the method answers per footprint.
// Throws Error with one line naming the problem.
void validate(const Scene& scene, const RenderSettings& settings);
// The same without the query (heightfield, wavelengths, footprint, options): what a caller can
// check before loading the heightfield.
void validate_view(const Scene& scene, const RenderSettings& settings);

// A square of the image seen on the patch, as a Gaussian: the square's box filter (covariance
// 1/12 of its side² per axis) carried to the plane z = 0 through the camera (the Jacobian J of the
// map from image to plane at the square's centre) has the covariance J diag(1/12, 1/12) Jᵀ side²,
// an ellipse whose principal standard deviations are major and minor (µm), the major one along
// the direction at axis_radians from the patch's +x.
struct SurfaceFootprint {
    double major_um = 0.0;
    double minor_um = 0.0;
    double axis_radians = 0.0;
    // The isotropic Gaussian of the same area (determinant): what a method that takes no ellipse weighs with.
    double equal_area_sigma_um() const;
};
// The footprint of the square of `side_pixels` centred at image point (x along columns from the
// left edge, y down rows from the top, in pixels). Throws Error if the point sees no plane.
SurfaceFootprint image_footprint(const PinholeCamera& camera, Point2 image_point, double side_pixels);

// One shading point of a pixel: where its camera ray meets the patch, the footprint's centre on
// the heightfield, ω_o toward the camera, and the footprint of its cell of the pixel (1/n of the
// pixel per side at n × n points) on the patch. `hit` false: the ray misses the patch.
struct ShadingPoint {
    bool hit = false;
    Vec3 position_um;
    Point2 heightfield_um;
    Vec3 omega_o;
    SurfaceFootprint cell;
};
std::vector<ShadingPoint> shading_points(const Scene& scene, const RenderSettings& settings, int row, int col);

// Whether the scene's method sees the pixel's footprint rather than the coherence footprint: a
// geometric method (not MethodInfo::wave_optics) renders the P-NDF of the pixel's footprint on the
// surface (Yan 2014/2016), the light's coherence being a wave effect.
bool renders_pixel_footprint(const std::string& method);

// The footprint whose BSDF a shading point evaluates from `field` (the scene's method's). A wave
// method: the query's coherence footprint centred at the point (Yan 2018 §3.1). A geometric
// method: the cell itself where the field answers rotated boxes (BsdfField::answers_rotated_boxes),
// as the rectangle of the cell's covariance centred at the point (sides √12 major × √12 minor,
// the width along its axis: the cell's area, cells of neighbouring points hardly overlapping);
// else the Gaussian whose surface weight |w|²/A_c (conventions.md, covariance Σ_c/2) has the cell's
// covariance: the ellipse itself (σ_c = √2 major, σ_minor = √2 minor, its axis) where the field
// answers ellipses (BsdfField::answers_ellipses), else the isotropic Gaussian of the same area
// (σ_c = √2 · equal_area_sigma). A point light subtends no solid angle,
// so the P-NDF's spikes are smoothed only by the method's option intrinsic_roughness (Yan 2014's
// intrinsic roughness; 0: a flat region's D is a spike, black away from exact reflection).
Footprint shading_footprint(const Scene& scene, const ShadingPoint& point, const BsdfField& field);

// Irradiance E = I cosθ_i / r² (W/m²) from a light at a shading point, and ω_i toward the light.
struct LightArrival {
    Vec3 omega_i;
    double irradiance = 0.0;
};
LightArrival light_arrival(const PointLight& light, Vec3 position_um);

// Scene text as the command line and manifests write it; lengths take unit suffixes (bare: µm).
// Each throws Error naming the text and the expected form.
Vec3 parse_position_um(const std::string& text);                          // "X,Y,Z"
void parse_camera(const std::string& text, PinholeCamera& camera);          // "X,Y,Z:LX,LY,LZ"
PointLight parse_light(const std::string& text);                            // "X,Y,Z:I" (I in W/sr)
void parse_image_size(const std::string& text, PinholeCamera& camera);      // "WIDTHxHEIGHT"

// The light sweep of Yan 2018's video: `frames` scenes (2 to 256) in which every light moves
// along the camera's right vector (horizontal) from −span/2 to +span/2 about its position, left
// to right as the camera sees it. Throws Error for a bad count or span, or a frame whose light
// would leave the valid range (validate).
std::vector<Scene> light_sweep(const Scene& scene, int frames, double span_um);

// The image: rows in parallel on settings.threads threads, each pixel summed in a fixed order, so
// the result is bit-identical for any thread count. progress(done, total) is called with rows done,
// one call at a time, from any of the threads.
RenderImage render(const Scene& scene, const RenderSettings& settings, const RunProgress& progress = {});

// The frames of light_sweep(scene, frames, span_um), each bit-identical to render() of that frame:
// the method's BSDF field is built once for all, and each shading point's BSDF once for all frames
// (the camera does not move). progress counts image rows, each done for every frame at once.
std::vector<RenderImage> render_light_sweep(const Scene& scene, int frames, double span_um, const RenderSettings& settings,
                                            const RunProgress& progress = {});

}  // namespace glintscope
