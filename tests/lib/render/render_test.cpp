// Rendering a lit patch (render.hpp): a flat mirror lights only the pixels where the light's mirror
// image lands, with the coherence window's transform times the irradiance; a tilted plane moves
// the highlight to its closed-form position; a pixel is the mean over its shading points of the
// BSDF contract's f_r times the irradiance; any thread count gives the same image; bad scenes
// are refused in one line before any work.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <thread>
#include <cmath>
#include <limits>
#include <string>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/fit/ndf_fit.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/optics/diffraction_model.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/render/render.hpp"

namespace glintscope {
namespace {

constexpr double kLambda = 0.5;
constexpr double kSigma = 10.0;

// A periodic field of `cols` × `rows` texels whose heights are slope · x (a plane when the
// patch stays within one period).
Heightfield plane_field(int cols, int rows, double texel_um, double slope) {
    Heightfield field;
    field.rows = rows;
    field.cols = cols;
    field.texel_um = texel_um;
    field.heights_um.resize(std::size_t(rows) * cols);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) field.at(r, c) = float(slope * (c + 0.5) * texel_um);
    return field;
}

// The camera and the light in the xz plane, the camera 45° up and 4.2 cm away.
Scene mirror_scene(Heightfield field, DiffractionModel model, double patch_um) {
    Scene scene;
    set_heightfield(scene.query, std::move(field));
    scene.query.wavelengths_um = {kLambda};
    scene.query.model = model;
    scene.query.footprint.sigma_um = kSigma;
    // The whole window's mass (the default 3.25 σ_c drops 0.5% of it, 1% of the intensity).
    scene.query.method_options["footprint_truncation"] = "5";
    scene.patch_um = patch_um;
    scene.camera.position_um = {-30000.0, 0.0, 30000.0};
    scene.camera.vertical_fov_degrees = 6.0;
    scene.camera.width = 64;
    scene.camera.height = 36;
    scene.lights = {PointLight{{30000.0, 0.0, 40000.0}, 2.0}};
    return scene;
}

// Where a pinhole camera (render.hpp's conventions) sees the point p, in pixel units (col, row).
Point2 project(const PinholeCamera& camera, Vec3 p) {
    const Vec3 forward = normalize(camera.look_at_um - camera.position_um);
    const Vec3 right = normalize(cross(forward, {0.0, 0.0, 1.0}));
    const Vec3 up = cross(right, forward);
    const Vec3 d = p - camera.position_um;
    const double tan_half = std::tan(0.5 * camera.vertical_fov_degrees * pi / 180.0);
    const double sx = dot(d, right) / dot(d, forward), sy = dot(d, up) / dot(d, forward);
    return {(sx / (tan_half * camera.width / camera.height) + 1.0) * 0.5 * camera.width,
            (1.0 - sy / tan_half) * 0.5 * camera.height};
}

struct Peak {
    int row = 0, col = 0;
    float value = 0.0f;
};
Peak brightest(const RenderImage& image) {
    Peak peak;
    for (int row = 0; row < image.height; ++row)
        for (int col = 0; col < image.width; ++col)
            if (image.at(0, row, col) > peak.value) peak = {row, col, image.at(0, row, col)};
    return peak;
}

// The flat patch's f_r for a Gaussian window (Yan 2018 eq. 3 with H = 0): ξ1/(λ² A_c) |W(ψ̄/λ)|²,
// W(v) = 2πσ² e^{−2π²σ²|v|²} the window's transform, A_c = πσ². Gabor kernels of width σ_k = l/2
// (Yan 2018 eq. 13; l = 1 µm here) represent the window blurred by their Gaussian, whose
// transform multiplies W by e^{−2π²σ_k²|v|²} (1.5% at the spot's edge, so it is part of the test).
double flat_mirror_f_r(DiffractionModel model, Vec3 omega_i, Vec3 omega_o) {
    constexpr double kKernelSigma = 0.5;
    const Vec3 psi = omega_i + omega_o;
    const double v2 = (psi.x * psi.x + psi.y * psi.y) / (kLambda * kLambda);
    const double transform = 2.0 * pi * kSigma * kSigma *
                             std::exp(-2.0 * pi * pi * (kSigma * kSigma + kKernelSigma * kKernelSigma) * v2);
    return xi1_geometric(model, omega_i, omega_o) / (kLambda * kLambda) * transform * transform / (pi * kSigma * kSigma);
}

TEST(Render, FlatMirrorLightsOnlyTheMirrorPointWithTheWindowTransformTimesTheIrradiance) {
    Scene scene = mirror_scene(plane_field(64, 64, 1.0, 0.0), DiffractionModel::rohs, 20000.0);
    const Vec3 camera = scene.camera.position_um, light = scene.lights[0].position_um;
    // The light's mirror image (x, y, −z) seen from the camera crosses z = 0 at the mirror point.
    const double t = camera.z / (camera.z + light.z);
    const Vec3 mirror_point = camera + t * (Vec3{light.x, light.y, -light.z} - camera);
    scene.camera.look_at_um = mirror_point + Vec3{600.0, 400.0, 0.0};  // off the image centre
    const RenderSettings settings{1, 0};
    const RenderImage image = render(scene, settings);
    const Peak peak = brightest(image);
    const Point2 expected = project(scene.camera, mirror_point);
    EXPECT_LE(std::fabs(peak.col + 0.5 - expected.x), 1.0) << "expected column " << expected.x;
    EXPECT_LE(std::fabs(peak.row + 0.5 - expected.y), 1.0) << "expected row " << expected.y;
    int lit = 0;
    for (int row = 0; row < image.height; ++row)
        for (int col = 0; col < image.width; ++col) {
            const float value = image.at(0, row, col);
            if (std::hypot(col + 0.5 - expected.x, row + 0.5 - expected.y) > 14.0) {
                EXPECT_LT(value, 1e-6 * peak.value) << "lit far from the mirror point at " << row << "," << col;
                continue;
            }
            if (value < 1e-3 * peak.value) continue;
            // The pixel centre's ray, independently of the renderer: E = I cosθ_i / r².
            const ShadingPoint point = shading_points(scene, settings, row, col).at(0);
            ASSERT_TRUE(point.hit);
            const Vec3 to_light = light - point.position_um;
            const double r = length(to_light);
            const Vec3 omega_i = (1.0 / r) * to_light;
            const Vec3 omega_o = normalize(camera - point.position_um);
            EXPECT_NEAR(dot(omega_o, point.omega_o), 1.0, 1e-12);
            const double irradiance = scene.lights[0].intensity_w_per_sr * omega_i.z / (r * r * 1e-12);
            const double expected_value = flat_mirror_f_r(scene.query.model, omega_i, omega_o) * irradiance;
            EXPECT_NEAR(value, expected_value, 0.01 * expected_value) << row << "," << col;
            ++lit;
        }
    EXPECT_GT(lit, 20);  // the spot spans many pixels, each checked
}

// GHS's phase ξ3 = ψ·n puts the lobe of a tilted plane H = a·x where ψ̄ + ψ_z H' = 0: the half
// vector is the plane's normal (−a, 0, 1), exact mirror reflection.
TEST(Render, TiltedPlaneMovesTheHighlightToItsMirrorPoint) {
    constexpr double slope = 0.03;
    // One period (16.4 mm) covers the 16 mm patch: no seam inside it.
    Scene scene = mirror_scene(plane_field(4096, 4, 4.0, slope), DiffractionModel::ghs, 16000.0);
    const Vec3 camera = scene.camera.position_um, light = scene.lights[0].position_um;
    const auto tilt_at = [&](double x) {  // ψ̄_x/ψ_z + a, decreasing in x
        const Vec3 p{x, 0.0, 0.0};
        const Vec3 psi = normalize(light - p) + normalize(camera - p);
        return psi.x / psi.z + slope;
    };
    double lo = -8000.0, hi = 8000.0;
    for (int k = 0; k < 100; ++k) (tilt_at(0.5 * (lo + hi)) > 0.0 ? lo : hi) = 0.5 * (lo + hi);
    const Vec3 highlight{0.5 * (lo + hi), 0.0, 0.0};
    const Vec3 flat_point = camera + (camera.z / (camera.z + light.z)) * (Vec3{light.x, light.y, -light.z} - camera);
    ASSERT_GT(std::fabs(highlight.x - flat_point.x), 900.0);  // the tilt moves it by many pixels
    scene.camera.look_at_um = 0.5 * (highlight + flat_point) + Vec3{0.0, 300.0, 0.0};
    const RenderImage image = render(scene, RenderSettings{1, 0});
    const Peak peak = brightest(image);
    const Point2 expected = project(scene.camera, highlight);
    const Point2 flat = project(scene.camera, flat_point);
    ASSERT_GT(std::hypot(expected.x - flat.x, expected.y - flat.y), 5.0);
    EXPECT_LE(std::fabs(peak.col + 0.5 - expected.x), 1.0) << "expected column " << expected.x;
    EXPECT_LE(std::fabs(peak.row + 0.5 - expected.y), 1.0) << "expected row " << expected.y;
}

Scene isotropic_scene() {
    static const Heightfield field = generate_builtin("isotropic");
    Scene scene;
    set_heightfield(scene.query, field);
    scene.query.wavelengths_um = {0.45, 0.6};
    scene.camera.width = 24;
    scene.camera.height = 14;
    scene.camera.vertical_fov_degrees = 3.0;  // a 4 mm view of the patch's centre, where the highlight is
    scene.lights = {PointLight{{0.0, 70710.0, 70710.0}, 1.0}, PointLight{{3000.0, 60000.0, 80000.0}, 0.5}};
    return scene;
}

TEST(Render, APixelIsTheMeanOfTheBsdfContractOverItsShadingPoints) {
    const Scene scene = isotropic_scene();
    const RenderSettings settings{4, 0};
    const RenderImage image = render(scene, settings);
    int checked = 0;
    for (const auto& [row, col] : {std::pair{7, 12}, {3, 5}, {10, 20}, {0, 0}, {13, 23}}) {
        std::vector<double> expected(image.wavelengths_um.size(), 0.0);
        for (const ShadingPoint& point : shading_points(scene, settings, row, col)) {
            ASSERT_TRUE(point.hit);
            LobeQuery query = scene.query;
            query.footprint.centre_um = point.heightfield_um;
            const Bsdf bsdf = make_bsdf("gabor", query);
            for (const PointLight& light : scene.lights) {
                const LightArrival arrival = light_arrival(light, point.position_um);
                const std::vector<double> f = bsdf.eval(arrival.omega_i, point.omega_o);
                for (std::size_t k = 0; k < f.size(); ++k) expected[k] += f[k] * arrival.irradiance / 4.0;
            }
        }
        for (std::size_t k = 0; k < expected.size(); ++k) {
            EXPECT_NEAR(image.at(k, row, col), expected[k], 1e-6 * expected[k]) << row << "," << col << " layer " << k;
            checked += expected[k] > 0.0;
        }
    }
    EXPECT_GE(checked, 6);  // glints, not black pixels
}

// Every shading point of a wave method weighs with the coherence footprint, so the render carries
// that footprint's BSDF warnings: none at σ_c = 10 µm; at 1 µm gabor's kernels (σ_k = 0.5 µm)
// keep f = 0.8 of the window's energy, and the image says so as the BSDF does.
TEST(Render, AWaveRenderCarriesItsFootprintsBsdfWarnings) {
    Scene scene = isotropic_scene();
    scene.camera.width = 4, scene.camera.height = 4;
    EXPECT_TRUE(render(scene, RenderSettings{1, 0}).warnings.empty());
    scene.query.footprint.sigma_um = 1.0;
    const std::vector<std::string> warnings = render(scene, RenderSettings{1, 0}).warnings;
    EXPECT_EQ(warnings, make_bsdf("gabor", scene.query).warnings());
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("gabor: the kernels' own blur"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("keeps f = 0.8 "), std::string::npos) << warnings[0];
}

TEST(Render, OneAndTwoThreadsGiveTheSameImage) {
    const Scene scene = isotropic_scene();
    const RenderImage one = render(scene, RenderSettings{4, 1});
    const RenderImage two = render(scene, RenderSettings{4, 2});
    EXPECT_EQ(one.values, two.values);
    EXPECT_GT(*std::max_element(one.values.begin(), one.values.end()), 0.0f);
}

// settings.threads = 0 keeps the caller's thread count (the CLI's --threads): inside a scope of
// one thread every row is rendered, and its progress reported, on the calling thread.
TEST(Render, ZeroThreadsKeepsTheCallersThreadCount) {
    const ThreadScope one(1);
    std::set<std::thread::id> threads;
    render(isotropic_scene(), RenderSettings{4, 0}, [&](std::size_t, std::size_t) { threads.insert(std::this_thread::get_id()); });
    EXPECT_EQ(threads, std::set<std::thread::id>{std::this_thread::get_id()});
}

// A sweep over glints (two lights, two wavelengths): each shading point evaluates all frames'
// lights in one eval_incident call, and each frame is still bit for bit the render of that frame
// alone, for 1 and 2 threads.
TEST(Render, ASweepOverGlintsIsEachFramesOwnRenderForAnyThreadCount) {
    const Scene scene = isotropic_scene();
    const std::vector<Scene> frames = light_sweep(scene, 3, 1500.0);
    const std::vector<RenderImage> one = render_light_sweep(scene, 3, 1500.0, RenderSettings{4, 1});
    const std::vector<RenderImage> two = render_light_sweep(scene, 3, 1500.0, RenderSettings{4, 2});
    ASSERT_EQ(one.size(), 3u);
    for (std::size_t k = 0; k < frames.size(); ++k) {
        EXPECT_EQ(one[k].values, two[k].values) << "frame " << k;
        EXPECT_EQ(one[k].values, render(frames[k], RenderSettings{4, 0}).values) << "frame " << k;
        EXPECT_GT(*std::max_element(one[k].values.begin(), one[k].values.end()), 0.0f) << "frame " << k;
    }
    EXPECT_NE(one[0].values, one[2].values);  // the glints move with the light
}

void expect_refused(const Scene& scene, const RenderSettings& settings, const std::string& words) {
    try {
        validate(scene, settings);
        ADD_FAILURE() << "accepted; expected a message with '" << words << "'";
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(words), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

TEST(Render, BadScenesAreRefusedInOneLine) {
    const Scene good = mirror_scene(plane_field(64, 64, 1.0, 0.0), DiffractionModel::rohs, 20000.0);
    const RenderSettings settings{4, 0};
    EXPECT_NO_THROW(validate(good, settings));
    Scene s = good;
    s.camera.position_um.z = -10.0;
    expect_refused(s, settings, "camera must be above");
    s = good;
    s.lights[0].position_um.z = 0.0;
    expect_refused(s, settings, "below the patch's horizon");
    s = good;
    s.camera.vertical_fov_degrees = 0.0;
    expect_refused(s, settings, "field of view");
    s = good;
    s.lights[0].position_um.x = std::nan("");
    expect_refused(s, settings, "finite");
    s = good;
    s.lights[0].intensity_w_per_sr = -1.0;
    expect_refused(s, settings, "intensity");
    s = good;
    s.camera.width = s.camera.height = 1000000;
    expect_refused(s, settings, "image size");
    s = good;
    s.camera.look_at_um = s.camera.position_um;
    expect_refused(s, settings, "looks at its own position");
    s = good;
    s.lights.clear();
    expect_refused(s, settings, "at least one light");
    expect_refused(good, RenderSettings{0, 0}, "spp");
    expect_refused(good, RenderSettings{3, 0}, "square");
    s = good;
    s.method = "stam";
    expect_refused(s, settings, "per shading point");
    s = good;
    Heightfield scan = plane_field(64, 64, 1.0, 0.0);
    scan.periodic = false;
    set_heightfield(s.query, scan);
    expect_refused(s, settings, "not periodic");
    s = good;
    s.method = "geometric";
    set_box(s.query.footprint, "70um");
    expect_refused(s, settings, "not the query's box");
    s = good;
    s.query.wavelengths_um = {-0.5};
    EXPECT_THROW(validate(s, settings), Error);
}

TEST(Render, SceneTextIsParsedWithUnits) {
    PinholeCamera camera;
    parse_camera("0,-7cm,7cm:1mm,0,0", camera);
    EXPECT_EQ(camera.position_um.y, -70000.0);
    EXPECT_EQ(camera.look_at_um.x, 1000.0);
    parse_image_size("64x36", camera);
    EXPECT_EQ(camera.width, 64);
    EXPECT_EQ(camera.height, 36);
    const PointLight light = parse_light("0,5cm,5cm:2.5");
    EXPECT_EQ(light.position_um.z, 50000.0);
    EXPECT_EQ(light.intensity_w_per_sr, 2.5);
    EXPECT_THROW(parse_light("0,5cm,5cm"), Error);
    EXPECT_THROW(parse_image_size("64x", camera), Error);
    EXPECT_THROW(parse_image_size("6.5x3", camera), Error);
    EXPECT_THROW(parse_camera("0,0:1,1,1", camera), Error);
}

}  // namespace
}  // namespace glintscope

namespace glintscope {
namespace {

// Yan 2018's light sweep: the lights move along the camera's right, so the mirror highlight of a
// flat patch moves left to right through the frames, each time to its closed-form point.
TEST(Render, ALightSweepMovesTheMirrorHighlightToEachFramesClosedFormPoint) {
    Scene scene = mirror_scene(plane_field(64, 64, 1.0, 0.0), DiffractionModel::rohs, 20000.0);
    const Vec3 camera = scene.camera.position_um, middle = scene.lights[0].position_um;
    const double middle_t = camera.z / (camera.z + middle.z);
    scene.camera.look_at_um = camera + middle_t * (Vec3{middle.x, middle.y, -middle.z} - camera);
    const std::vector<Scene> sweep = light_sweep(scene, 3, 3000.0);
    const std::vector<RenderImage> images = render_light_sweep(scene, 3, 3000.0, RenderSettings{1, 0});
    ASSERT_EQ(sweep.size(), 3u);
    ASSERT_EQ(images.size(), 3u);
    int previous_col = -1;
    for (std::size_t k = 0; k < sweep.size(); ++k) {
        const Scene& frame = sweep[k];
        // One BSDF field for all frames gives what a render of each frame alone gives.
        EXPECT_EQ(images[k].values, render(frame, RenderSettings{1, 0}).values);
        const Vec3 light = frame.lights[0].position_um;
        EXPECT_EQ(light.z, scene.lights[0].position_um.z);  // moved horizontally
        const double t = camera.z / (camera.z + light.z);
        const Vec3 mirror_point = camera + t * (Vec3{light.x, light.y, -light.z} - camera);
        const Peak peak = brightest(images[k]);
        const Point2 expected = project(frame.camera, mirror_point);
        EXPECT_LE(std::fabs(peak.col + 0.5 - expected.x), 1.0) << "expected column " << expected.x;
        EXPECT_LE(std::fabs(peak.row + 0.5 - expected.y), 1.0) << "expected row " << expected.y;
        EXPECT_GT(peak.col, previous_col + 3);  // left to right, several pixels per frame
        previous_col = peak.col;
    }
    EXPECT_THROW(light_sweep(scene, 1, 3000.0), Error);
    EXPECT_THROW(light_sweep(scene, 3, -1.0), Error);
    EXPECT_THROW(light_sweep(scene, 3, std::numeric_limits<double>::infinity()), Error);
}

}  // namespace
}  // namespace glintscope

namespace glintscope {
namespace {

// Where the camera's ray through image point p (pixels, render.hpp's conventions) meets z = 0.
Vec3 unproject(const PinholeCamera& camera, Point2 p) {
    const Vec3 forward = normalize(camera.look_at_um - camera.position_um);
    const Vec3 right = normalize(cross(forward, {0.0, 0.0, 1.0}));
    const Vec3 up = cross(right, forward);
    const double tan_half = std::tan(0.5 * camera.vertical_fov_degrees * pi / 180.0);
    const double sx = (2.0 * p.x / camera.width - 1.0) * tan_half * camera.width / camera.height;
    const double sy = (1.0 - 2.0 * p.y / camera.height) * tan_half;
    const Vec3 d = forward + sx * right + sy * up;
    return camera.position_um + (-camera.position_um.z / d.z) * d;
}

// A geometric render sees each pixel's footprint on the patch (Yan 2014/2016), the cell's: its
// box filter's covariance through the camera, whose determinant is (area/12)² for the pixel's
// quadrilateral on the patch, foreshortened by 1/cos 45° along the view at the Patch scene's
// centre, and half as wide in an image of twice the size.
TEST(Render, APixelsFootprintIsItsQuadrilateralOnThePatchAndHalvesWhenTheImageDoubles) {
    PinholeCamera camera;  // the Patch scene's: 10 cm away, 45° elevation
    camera.width = 64;
    camera.height = 36;
    const SurfaceFootprint centre = image_footprint(camera, {32.0, 18.0}, 1.0);
    EXPECT_NEAR(centre.major_um / centre.minor_um, std::sqrt(2.0), 1e-9);
    EXPECT_NEAR(centre.minor_um, 1e5 * 2.0 * std::tan(15.0 * pi / 180.0) / 36.0 / std::sqrt(12.0), 1e-9 * centre.minor_um);
    PinholeCamera twice = camera;
    twice.width = 128;
    twice.height = 72;
    for (const Point2 p : {Point2{32.0, 18.0}, {5.5, 3.5}, {60.5, 30.5}, {40.25, 2.0}}) {
        const SurfaceFootprint one = image_footprint(camera, p, 1.0);
        const Vec3 a = unproject(camera, {p.x - 0.5, p.y - 0.5}), b = unproject(camera, {p.x + 0.5, p.y - 0.5});
        const Vec3 c = unproject(camera, {p.x + 0.5, p.y + 0.5}), d = unproject(camera, {p.x - 0.5, p.y + 0.5});
        const double area = 0.5 * std::fabs(cross(c - a, d - b).z);  // a quadrilateral: half its diagonals' cross product
        EXPECT_NEAR(12.0 * one.major_um * one.minor_um, area, 1e-3 * area) << p.x << "," << p.y;
        const SurfaceFootprint half = image_footprint(twice, {2.0 * p.x, 2.0 * p.y}, 1.0);
        EXPECT_NEAR(half.major_um, 0.5 * one.major_um, 1e-9 * one.major_um);
        EXPECT_NEAR(half.minor_um, 0.5 * one.minor_um, 1e-9 * one.minor_um);
    }
    // Shading points carry their cell's footprint (half a pixel per side at 2 × 2), and a
    // geometric method evaluates the cell as the rectangle of its covariance (sides √12 major ×
    // √12 minor along its axis), or the Gaussian of its area where its settings take neither a
    // rotated box nor an ellipse (shadowing answers from images); a wave method its coherence
    // footprint.
    Scene scene;
    set_heightfield(scene.query, plane_field(64, 64, 1.0, 0.0));
    scene.camera = camera;
    const ShadingPoint point = shading_points(scene, RenderSettings{4, 0}, 20, 30).at(3);
    const SurfaceFootprint cell = image_footprint(camera, {30.75, 20.75}, 0.5);
    EXPECT_DOUBLE_EQ(point.cell.major_um, cell.major_um);
    EXPECT_DOUBLE_EQ(point.cell.minor_um, cell.minor_um);
    EXPECT_DOUBLE_EQ(point.cell.axis_radians, cell.axis_radians);
    scene.method = "geometric";
    const BsdfField geometric = make_bsdf_field("geometric", scene.query);
    EXPECT_TRUE(geometric.answers_rotated_boxes());
    const Footprint rectangle = shading_footprint(scene, point, geometric);
    EXPECT_EQ(rectangle.shape, FootprintShape::box);
    EXPECT_DOUBLE_EQ(box_width_um(rectangle), std::sqrt(12.0) * cell.major_um);
    EXPECT_DOUBLE_EQ(box_height_um(rectangle), std::sqrt(12.0) * cell.minor_um);
    EXPECT_DOUBLE_EQ(rectangle.axis_radians, cell.axis_radians);
    EXPECT_TRUE(is_rotated_box(rectangle));
    EXPECT_EQ(rectangle.centre_um.x, point.heightfield_um.x);
    EXPECT_EQ(rectangle.centre_um.y, point.heightfield_um.y);
    scene.query.method_options["shadowing"] = "smith";
    const BsdfField shadowed = make_bsdf_field("geometric", scene.query);
    EXPECT_FALSE(shadowed.answers_rotated_boxes());
    EXPECT_THROW(shadowed.at(rectangle), Error);  // its images' boxes are axis-aligned
    const Footprint circle = shading_footprint(scene, point, shadowed);
    EXPECT_EQ(circle.shape, FootprintShape::gaussian);
    EXPECT_DOUBLE_EQ(circle.sigma_um, std::sqrt(2.0 * cell.major_um * cell.minor_um));
    EXPECT_FALSE(is_elliptical(circle));
    Footprint ellipse = circle;
    ellipse.sigma_minor_um = 0.5 * circle.sigma_um;
    scene.query.method_options.clear();
    scene.method = "gabor";
    const BsdfField gabor = make_bsdf_field("gabor", scene.query);
    EXPECT_EQ(shading_footprint(scene, point, gabor).sigma_um, scene.query.footprint.sigma_um);
    EXPECT_FALSE(gabor.answers_ellipses());
    EXPECT_FALSE(gabor.answers_rotated_boxes());
    EXPECT_THROW(gabor.at(ellipse), Error);  // it would weigh by σ_c alone
    EXPECT_THROW(gabor.at(rectangle), Error);  // its window would be the axis-aligned box
}

// A camera tilted θ from the patch's normal, looking at the patch: at the image's centre the
// pixel's footprint is an ellipse foreshortened 1/cos θ along the view's azimuth φ and unchanged
// across it (the closed form of the Jacobian there: the image's right vector lies in the plane,
// its up vector leaves it at θ).
TEST(Render, ATiltedCamerasCentrePixelIsAnEllipseOfRatioOneOverCosTheta) {
    for (const double theta_degrees : {30.0, 60.0, 75.0})
        for (const double phi_degrees : {-120.0, 30.0}) {
            const double theta = theta_degrees * pi / 180.0, phi = phi_degrees * pi / 180.0, distance = 1e5;
            PinholeCamera camera;
            camera.width = 64;
            camera.height = 36;
            camera.position_um = {distance * std::sin(theta) * std::cos(phi), distance * std::sin(theta) * std::sin(phi),
                                  distance * std::cos(theta)};
            camera.look_at_um = {0.0, 0.0, 0.0};
            const SurfaceFootprint centre = image_footprint(camera, {32.0, 18.0}, 1.0);
            EXPECT_NEAR(centre.major_um / centre.minor_um, 1.0 / std::cos(theta), 1e-9) << theta_degrees;
            const double side = distance * 2.0 * std::tan(0.5 * camera.vertical_fov_degrees * pi / 180.0) / 36.0;
            EXPECT_NEAR(centre.minor_um, side / std::sqrt(12.0), 1e-9 * side);
            // The major axis along ±(cos φ, sin φ): the same line whatever its sign.
            EXPECT_NEAR(std::fabs(std::sin(centre.axis_radians - phi)), 0.0, 1e-9) << theta_degrees << "," << phi_degrees;
        }
}

// A flat mirror rendered geometrically with intrinsic roughness σ (a point light needs it: the
// P-NDF of a flat footprint is a spike): the camera's irradiance over the image,
// Σ L Ω cosθ (Ω = p² cos³θ a pixel's solid angle, θ from the axis), is what the light's mirror
// image sends it, F I / d² with d the path camera → mirror point → light, and F the material's
// Fresnel reflectance at the mirror point: the render neither creates nor loses reflected power.
TEST(Render, AGeometricFlatMirrorSendsTheCameraTheLightsMirrorImageTimesFresnel) {
    Scene scene;
    set_heightfield(scene.query, plane_field(16, 16, 16.0, 0.0));
    scene.method = "geometric";
    scene.query.wavelengths_um = {0.5};
    scene.query.material.name = "Al";
    scene.query.method_options["intrinsic_roughness"] = "0.01";
    scene.patch_um = 40000.0;
    scene.camera.position_um = {-30000.0, 0.0, 30000.0};
    scene.camera.vertical_fov_degrees = 10.0;
    scene.camera.width = scene.camera.height = 72;
    scene.lights = {PointLight{{30000.0, 0.0, 40000.0}, 2.0}};
    const Vec3 camera = scene.camera.position_um, light = scene.lights[0].position_um;
    const Vec3 mirror_point = camera + (camera.z / (camera.z + light.z)) * (Vec3{light.x, light.y, -light.z} - camera);
    scene.camera.look_at_um = mirror_point;
    const RenderImage image = render(scene, RenderSettings{1, 0});
    const double p = 2.0 * std::tan(5.0 * pi / 180.0) / 72.0;
    double irradiance = 0.0, edge = 0.0, peak = 0.0;
    for (int row = 0; row < 72; ++row)
        for (int col = 0; col < 72; ++col) {
            const double sx = (col + 0.5 - 36.0) * p, sy = (36.0 - row - 0.5) * p;
            const double cos_axis = 1.0 / std::sqrt(1.0 + sx * sx + sy * sy);
            const double value = image.at(0, row, col);
            irradiance += value * p * p * std::pow(cos_axis, 4);
            peak = std::max(peak, value);
            if (row == 0 || col == 0 || row == 71 || col == 71) edge = std::max(edge, value);
        }
    EXPECT_LT(edge, 1e-6 * peak);  // the whole highlight is in the image
    const double d = length(light - mirror_point) + length(camera - mirror_point);
    const double cos_i = (light.z - 0.0) / length(light - mirror_point);
    const double fresnel = fresnel_conductor(complex_refractive_index("Al", 0.5), cos_i);
    const double expected = fresnel * 2.0 / (d * d * 1e-12);
    RecordProperty("irradiance_over_expected_minus_1", ::testing::PrintToString(irradiance / expected - 1.0));  // measured 1.9e-5
    EXPECT_NEAR(irradiance, expected, 2e-3 * expected) << "F = " << fresnel;
}

// A geometric pixel is the mean over its shading points of the method's BSDF field at the
// rectangle of the cell's footprint (computed here from image_footprint: its covariance's
// rectangle), times the irradiance.
TEST(Render, AGeometricPixelIsTheFieldsBsdfAtItsCellsFootprint) {
    static const Heightfield field = generate_builtin("isotropic");
    Scene scene;
    set_heightfield(scene.query, field);
    scene.method = "geometric";
    scene.query.wavelengths_um = {0.5};
    scene.camera.width = 12;
    scene.camera.height = 8;
    scene.camera.vertical_fov_degrees = 0.4;  // 50 um pixels about the patch's centre, the highlight
    const RenderSettings settings{4, 0};
    const RenderImage image = render(scene, settings);
    EXPECT_NE(image.metadata.at("render.footprint").find("rectangle of its covariance"), std::string::npos);
    LobeQuery query = scene.query;
    const BsdfField bsdfs = make_bsdf_field("geometric", query);
    int lit = 0;
    for (int row = 0; row < 8; ++row)
        for (int col = 0; col < 12; ++col) {
            double expected = 0.0;
            const std::vector<ShadingPoint> points = shading_points(scene, settings, row, col);
            for (int k = 0; k < 4; ++k) {
                const ShadingPoint& point = points[k];
                const SurfaceFootprint cell = image_footprint(scene.camera, {col + 0.25 + 0.5 * (k % 2), row + 0.25 + 0.5 * (k / 2)}, 0.5);
                Footprint footprint;  // the cell's rectangle: a side a has variance a²/12
                footprint.centre_um = point.heightfield_um;
                footprint.shape = FootprintShape::box;
                footprint.size_um = std::sqrt(12.0) * cell.major_um;
                footprint.size_y_um = std::sqrt(12.0) * cell.minor_um;
                footprint.axis_radians = cell.axis_radians;
                const LightArrival arrival = light_arrival(scene.lights[0], point.position_um);
                expected += bsdfs.at(footprint).eval(arrival.omega_i, point.omega_o)[0] * arrival.irradiance / 4.0;
            }
            EXPECT_NEAR(image.at(0, row, col), expected, 1e-6 * expected) << row << "," << col;
            lit += expected > 0.0;
        }
    EXPECT_GT(lit, 20);
}

// A Gaussian random field, 128² at 1 µm (period 128 µm), Gaussian correlation of 5 µm and rms
// height 0.6 µm: Gaussian slopes of rms 0.17 per axis.
Heightfield gaussian_surface() {
    Recipe recipe;
    recipe.kind = "gaussian";
    recipe.grid = {128, 128, 1.0};
    recipe.gaussian.sigma_h_um = 0.6;
    recipe.gaussian.correlation_length_x_um = recipe.gaussian.correlation_length_y_um = 5.0;
    return generate(recipe);
}

// The smooth baseline (method fitted) renders the closed-form microfacet BRDF F D / (4 cosθ_i cosθ_o)
// of the Beckmann model fitted to the whole field's P-NDF (fitted here from pndf's image) times
// each pixel's irradiance: a highlight without glints to compare glint renders with.
TEST(Render, TheFittedBaselineIsTheClosedFormMicrofacetBrdfTimesTheIrradiance) {
    Scene scene;
    set_heightfield(scene.query, gaussian_surface());
    scene.method = "fitted";
    scene.query.wavelengths_um = {0.5};
    scene.query.material.name = "Al";
    scene.camera.width = 24;
    scene.camera.height = 14;
    const RenderSettings settings{1, 0};
    const RenderImage image = render(scene, settings);
    LobeQuery ndf_query = scene.query;
    ndf_query.quantity = Quantity::ndf;
    ndf_query.footprint.shape = FootprintShape::whole;
    ndf_query.resolution = 128;
    ndf_query.material = {};
    const EllipsoidNdf alpha = fit_ndf(compute_lobe("pndf", ndf_query), NdfModelKind::beckmann).model.parameters;
    for (const auto& [row, col] : {std::pair{7, 12}, {5, 9}, {12, 10}, {9, 15}}) {
        const ShadingPoint point = shading_points(scene, settings, row, col).at(0);
        ASSERT_TRUE(point.hit);
        const LightArrival arrival = light_arrival(scene.lights[0], point.position_um);
        const Vec3 h = normalize(arrival.omega_i + point.omega_o);
        const double fresnel = fresnel_conductor(complex_refractive_index("Al", 0.5), dot(arrival.omega_i, h));
        const double expected = fresnel * beckmann_ndf(alpha.alpha_x, alpha.alpha_y, h) /
                                (4.0 * arrival.omega_i.z * point.omega_o.z) * arrival.irradiance;  // Dong 2015 eq. 1
        EXPECT_NEAR(image.at(0, row, col), expected, 1e-5 * expected) << row << "," << col;
        EXPECT_GT(expected, 0.0);
    }
}

// A camera 10 m straight above the patch, its image exactly the patch: pixels are squares of
// side patch/size on it, and ω_o is the normal to within side/10 m.
Scene overhead_scene(double patch_um, int size) {
    Scene scene;
    scene.patch_um = patch_um;
    scene.camera.position_um = {0.0, 0.0, 1e7};
    scene.camera.look_at_um = {0.0, 0.0, 0.0};
    scene.camera.vertical_fov_degrees = 2.0 * std::atan(0.5 * patch_um / 1e7) * 180.0 / pi;
    scene.camera.width = scene.camera.height = size;
    return scene;
}

// Averages: a rough surface (4.3 × 4.3 periods) lit by a distant light and seen by a distant
// camera: the mean of the geometric render over the region, whose pixels see the P-NDFs of their
// own footprints (glints), equals the render with the footprint-averaged lobe, the whole field's
// (every point of a period weighs the same), E f_r(ω_i, ω_o; whole) per pixel (2%). A P-NDF at a
// single h is dominated by the few points near its caustics (their 1/|det| weights have no finite
// variance), so the intrinsic roughness 0.01 makes each pixel's D an average over nearby h.
TEST(Render, TheMeanOfAGeometricRenderOverARoughRegionIsTheRenderOfTheMeanLobe) {
    Scene scene = overhead_scene(550.0, 32);
    set_heightfield(scene.query, gaussian_surface());
    scene.method = "geometric";
    scene.query.wavelengths_um = {0.5};
    scene.query.method_options["intrinsic_roughness"] = "0.01";
    scene.lights = {PointLight{{0.25 * 1e7, 0.1 * 1e7, 1e7}, 1.0}};  // ω_i about 15° from the normal
    const RenderSettings settings{1, 0};
    const RenderImage image = render(scene, settings);
    LobeQuery query = scene.query;
    const BsdfField field = make_bsdf_field("geometric", query);
    Footprint whole;
    whole.shape = FootprintShape::whole;
    const Bsdf mean_lobe = field.at(whole);
    // Both distances are 10 m: ω_i and ω_o vary by 3e-5 rad over the region, a thousandth of the
    // intrinsic roughness, so the mean lobe is taken at the centre's directions.
    const ShadingPoint centre = shading_points(scene, RenderSettings{1, 0}, 16, 16).at(0);
    const double f_mean = mean_lobe.eval(light_arrival(scene.lights[0], centre.position_um).omega_i, centre.omega_o)[0];
    double rendered = 0.0, expected = 0.0, brightest = 0.0, faintest = INFINITY;
    for (int row = 0; row < 32; ++row)
        for (int col = 0; col < 32; ++col) {
            const ShadingPoint point = shading_points(scene, RenderSettings{1, 0}, row, col).at(0);
            expected += f_mean * light_arrival(scene.lights[0], point.position_um).irradiance;
            rendered += image.at(0, row, col);
            brightest = std::max(brightest, double(image.at(0, row, col)));
            faintest = std::min(faintest, double(image.at(0, row, col)));
        }
    EXPECT_GT(brightest, 2.0 * faintest);  // glints: the pixels differ, their mean does not
    RecordProperty("rendered_over_expected_minus_1", ::testing::PrintToString(rendered / expected - 1.0));
    EXPECT_NEAR(rendered, expected, 0.02 * expected);  // measured 0.14% with box cells (0.5% with ellipses)
}

// Energy: a light 2 mm above a 60 mm patch seen from 10 m straight above. By reciprocity
// (f_r(ω_i, ω_o) = f_r(ω_o, ω_i)) and dω_i = cosθ_i dA / r² as seen from the light,
// ∫ L cosθ_i dA = I ∫ f_r(ω_i, ω_o) cosθ_i dω_i = I · albedo(ω_o): the render sends the camera what
// the BSDF's albedo says, for the smooth baseline with aluminium's F (the patch spans θ_i up to
// 86°; the lobe beyond holds under 1e-6 of the albedo).
TEST(Render, ARenderReflectsTheLightAsTheBsdfsAlbedoSays) {
    constexpr double patch = 60000.0, height = 2000.0;
    constexpr int size = 240;
    Scene scene = overhead_scene(patch, size);
    set_heightfield(scene.query, gaussian_surface());
    scene.method = "fitted";
    scene.query.wavelengths_um = {0.5};
    scene.query.material.name = "Al";
    scene.lights = {PointLight{{0.0, 0.0, height}, 3.0}};
    const RenderImage image = render(scene, RenderSettings{16, 0});
    const double side = patch / size;
    double integral = 0.0;  // ∫ L cosθ_i dA in W/sr (dA in m²)
    for (int row = 0; row < size; ++row)
        for (int col = 0; col < size; ++col) {
            const Vec3 x{(col + 0.5) * side - 0.5 * patch, 0.5 * patch - (row + 0.5) * side, 0.0};
            const double cos_i = height / length(scene.lights[0].position_um - x);
            integral += image.at(0, row, col) * cos_i * side * side * 1e-12;
        }
    const Vec3 omega_o{0.0, 0.0, 1.0};
    const double albedo = make_bsdf("fitted", scene.query).albedo(omega_o)[0];
    EXPECT_GT(albedo, 0.85);  // aluminium's F near normal incidence
    EXPECT_NEAR(integral, 3.0 * albedo, 0.01 * 3.0 * albedo);
}

}  // namespace
}  // namespace glintscope
