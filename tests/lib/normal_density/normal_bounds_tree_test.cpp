// The point query of the exact normal density against its image: the image's pixel is the mean
// of the point query over the pixel, point values at pixel centres match a smooth surface's
// image, also for an elliptical footprint (whose D on a sphere cap is its Gaussian), ∫ D dA = 1, a tilted plane's D sits at its normal, pruning changes nothing, threads
// change nothing, a footprint straddling the field's edge reads the tiles on both sides,
// intrinsic roughness matches the image's blur, and the sampler's draws of h fall in the image's
// pixels with their masses; box footprints, rotated too, partition the density by the preimage
// rule, meet a paraboloid's closed form, and are sampled with their queried density.
#include "normal_density/normal_bounds_tree.hpp"

#include <gtest/gtest.h>

#include "relative_l2.hpp"
#include "disk_chi_square.hpp"
#include "core/counter_rng.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <thread>

#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"
#include "normal_density/normal_density.hpp"
#include "sampled_field.hpp"

namespace glintscope {
namespace {

using testing::isotropic_field;
using testing::sampled_field;

Footprint gaussian_at(Point2 centre, double sigma) {
    Footprint footprint;
    footprint.centre_um = centre;
    footprint.sigma_um = sigma;
    return footprint;
}

// A box of sides width × height, its width along the axis at `axis` radians from +x.
Footprint box_at(Point2 centre, double width, double height, double axis) {
    Footprint footprint;
    footprint.centre_um = centre;
    footprint.shape = FootprintShape::box;
    footprint.size_um = width;
    footprint.size_y_um = height;
    footprint.axis_radians = axis;
    return footprint;
}

// An elliptical Gaussian footprint: σ_c along the axis at `axis` radians from +x, σ_minor across.
Footprint ellipse_at(Point2 centre, double sigma, double sigma_minor, double axis) {
    Footprint footprint = gaussian_at(centre, sigma);
    footprint.sigma_minor_um = sigma_minor;
    footprint.axis_radians = axis;
    return footprint;
}

// The mean of the point query over K × K points of each pixel (zero for pixels whose centre lies
// outside the disk, as the image's).
std::vector<double> pixel_means(const NormalBoundsTree& tree, const Footprint& footprint, int resolution, int k) {
    std::vector<double> means(static_cast<std::size_t>(resolution) * resolution, 0.0);
    for (int row = 0; row < resolution; ++row)
        for (int col = 0; col < resolution; ++col) {
            if (!inside_unit_disk(disk_pixel_point(row, col, resolution))) continue;
            double sum = 0.0;
            for (int b = 0; b < k; ++b)
                for (int a = 0; a < k; ++a)
                    sum += point_normal_density(tree, footprint, disk_subpixel_point(row, col, b, a, resolution, k));
            means[static_cast<std::size_t>(row) * resolution + col] = sum / (k * k);
        }
    return means;
}

using testing::relative_l2;

TEST(NormalBoundsTree, PixelMeanOfThePointQueryIsTheImagePixel) {
    // The same triangles (adaptive subdivision included): the image holds each pixel's exact
    // share, the K × K mean is a quadrature of it. On a rough surface the folds' caustics make D
    // singular (as 1/√distance), so the quadrature converges slowly: measured at N = 16, relative
    // L2 over the image 0.36 (K = 4), 0.033 (K = 16), and at the 3 largest pixels K = 256 is
    // within 0.5% of each (K = 512: 0.2%, reaching the image as K grows).
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(96));
    const Footprint footprint = gaussian_at({40.0, 50.0}, 8.0);
    const int n = 16;
    const NormalDensitySettings settings;
    ASSERT_GT(settings.tolerance_pixels, 0.0);
    const std::vector<double> image = normal_density(*surface, footprint, n, settings);
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, settings, n);
    const double error = relative_l2(pixel_means(tree, footprint, n, 16), image);
    RecordProperty("relative_l2_k16", ::testing::PrintToString(error));
    EXPECT_LT(error, 0.05);
    std::vector<int> largest(image.size());
    for (std::size_t k = 0; k < image.size(); ++k) largest[k] = static_cast<int>(k);
    std::partial_sort(largest.begin(), largest.begin() + 3, largest.end(), [&](int a, int b) { return image[a] > image[b]; });
    for (int i = 0; i < 3; ++i) {
        const int row = largest[i] / n, col = largest[i] % n, k = 256;
        double sum = 0.0;
        for (int b = 0; b < k; ++b)
            for (int a = 0; a < k; ++a) sum += point_normal_density(tree, footprint, disk_subpixel_point(row, col, b, a, n, k));
        EXPECT_NEAR(sum / (k * k), image[largest[i]], 0.01 * image[largest[i]]) << row << "," << col;
    }
}

TEST(NormalBoundsTree, EllipticalPixelMeansAreTheImagesPixels) {
    // The image and the query weigh the same triangles by the ellipse's weight (covariance Σ_c/2):
    // as for a circle above, the K × K means of the query reach the image's pixels, more slowly
    // for the narrow minor axis (σ_w 3.5 µm; measured relative L2 at N = 16: 0.057 at K = 16,
    // 0.027 at K = 32); the same ellipse turned by 90° is far off (0.50 at K = 4).
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(96));
    const Footprint footprint = ellipse_at({40.0, 50.0}, 11.0, 5.0, 1.0);
    const int n = 16;
    const NormalDensitySettings settings;
    const std::vector<double> image = normal_density(*surface, footprint, n, settings);
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, settings, n);
    const double error = relative_l2(pixel_means(tree, footprint, n, 32), image);
    RecordProperty("relative_l2_k32", ::testing::PrintToString(error));
    EXPECT_LT(error, 0.04);
    const double turned = relative_l2(pixel_means(tree, ellipse_at({40.0, 50.0}, 11.0, 5.0, 1.0 + 0.5 * pi), n, 4), image);
    RecordProperty("relative_l2_turned", ::testing::PrintToString(turned));
    EXPECT_GT(turned, 0.3);
}

TEST(NormalBoundsTree, EllipticalFootprintOnASphereCapIsAGaussianOfItsCovariance) {
    // On a cap H = √(R² − |s − o|²) the normal's disk point is (s − o)/R exactly, so an elliptical
    // footprint's weight, the Gaussian of covariance Σ_c/2 about x_c (footprint.hpp), maps to the
    // Gaussian of mean (x_c − o)/R and covariance Σ_c/(2R²) on the disk. The point values carry the
    // centroid rule's steps (a triangle's D is the weight at its centroid, up to half a texel from
    // h's preimage: ~|s − x_c| texel/(2σ_w²) relative, 25% at 2.5σ_w across the 4.9 µm minor axis):
    // measured relative L2 0.034 over a grid of h reaching 2.5σ_w of the major axis; the closed
    // form of the ellipse turned by 90° is 0.73 away.
    const double radius = 200.0;
    const Point2 origin{96.0, 96.0}, centre{116.0, 86.0};
    const auto surface = std::make_shared<const BicubicInterpolant>(sampled_field(192, 192, 1.0, [&](double x, double y) {
        return std::sqrt(radius * radius - (x - origin.x) * (x - origin.x) - (y - origin.y) * (y - origin.y));
    }));
    const double sigma_c = 16.0, sigma_minor = 7.0, axis = 0.5;
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, {}, 128);
    const auto closed_form = [&](double turn, DiskPoint h) {
        const double c = std::cos(axis + turn), s = std::sin(axis + turn);
        const double major = 0.5 * sigma_c * sigma_c / (radius * radius), minor = 0.5 * sigma_minor * sigma_minor / (radius * radius);
        const double dx = h.x - (centre.x - origin.x) / radius, dy = h.y - (centre.y - origin.y) / radius;
        const double along = c * dx + s * dy, across = -s * dx + c * dy;
        return std::exp(-0.5 * (along * along / major + across * across / minor)) / (2.0 * pi * std::sqrt(major * minor));
    };
    std::vector<double> measured, expected, turned;
    const double reach = 2.5 * sigma_c / std::numbers::sqrt2 / radius;
    for (int b = -10; b <= 10; ++b)
        for (int a = -10; a <= 10; ++a) {
            const DiskPoint h{(centre.x - origin.x) / radius + reach * a / 10.0, (centre.y - origin.y) / radius + reach * b / 10.0};
            measured.push_back(point_normal_density(tree, ellipse_at(centre, sigma_c, sigma_minor, axis), h));
            expected.push_back(closed_form(0.0, h));
            turned.push_back(closed_form(0.5 * pi, h));
        }
    const double error = relative_l2(measured, expected);
    RecordProperty("relative_l2", ::testing::PrintToString(error));
    EXPECT_LT(error, 0.05);
    EXPECT_GT(relative_l2(turned, expected), 0.5);
}

TEST(NormalBoundsTree, AnEllipseOfEqualAxesIsTheCircle) {
    // The elliptical weight (its quadratic form, normalisation and Mahalanobis cutoff) against the
    // isotropic one at a minor σ within 1e-12 of σ_c, at any axis: equal to rounding.
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(64));
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, {}, 64);
    const Footprint circle = gaussian_at({20.0, 30.0}, 7.0);
    int nonzero = 0;
    for (int k = 0; k < 40; ++k) {
        const DiskPoint h{0.25 * std::cos(0.9 * k) * (k % 7) / 7.0, 0.25 * std::sin(0.9 * k) * (k % 5) / 5.0};
        const double expected = point_normal_density(tree, circle, h);
        const double ellipse = point_normal_density(tree, ellipse_at({20.0, 30.0}, 7.0, 7.0 * (1.0 - 1e-12), 0.3 * k), h);
        EXPECT_NEAR(ellipse, expected, 1e-9 * expected) << k;
        nonzero += expected > 0.0;
    }
    EXPECT_GT(nonzero, 20);
}

// A quadratic heightfield about `origin` (no folds: its normal map is one to one), 128² at 1 µm.
std::shared_ptr<const BicubicInterpolant> quadratic_surface(double a, double b, double c, Point2 origin) {
    return std::make_shared<const BicubicInterpolant>(sampled_field(128, 128, 1.0, [=](double x, double y) {
        const double u = x - origin.x, v = y - origin.y;
        return 0.5 * a * u * u + 0.5 * b * v * v + c * u * v;
    }));
}

// Relative L2 of the point query against the undivided image at N = 64 (the field's seam would
// otherwise be divided 64-fold): at the pixel centres and for the 4 × 4 means, both recorded.
struct ImageAgreement {
    double centres = 0.0, means = 0.0;
};

ImageAgreement agreement_with_image(const std::shared_ptr<const BicubicInterpolant>& surface, const Footprint& footprint) {
    const int n = 64;
    const NormalDensitySettings undivided{1, 0.0, 0.0};
    const std::vector<double> image = normal_density(*surface, footprint, n, undivided);
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, undivided, n);
    const ImageAgreement agreement{relative_l2(pixel_means(tree, footprint, n, 1), image),
                                   relative_l2(pixel_means(tree, footprint, n, 4), image)};
    ::testing::Test::RecordProperty("relative_l2_centres", ::testing::PrintToString(agreement.centres));
    ::testing::Test::RecordProperty("relative_l2_k4", ::testing::PrintToString(agreement.means));
    return agreement;
}

TEST(NormalBoundsTree, PointValuesAtPixelCentresMatchASmoothSurfacesImage) {
    // A paraboloid patch (a Gaussian in slope space, normal_density_test.cpp): D is smooth but
    // for the steps between neighbouring triangles' centroid weights (about texel/σ_w of the
    // weight), which a pixel's mean smooths out. Measured relative L2 at N = 64, σ_c = 20 µm:
    // 0.018 at the pixel centres, 0.0021 for the 4 × 4 means (σ_c = 10 µm: 0.049 and 0.0060).
    const ImageAgreement agreement =
        agreement_with_image(quadratic_surface(0.008, 0.006, 0.002, {58.0, 70.0}), gaussian_at({64.0, 64.0}, 20.0));
    EXPECT_LT(agreement.centres, 0.025);
    EXPECT_LT(agreement.means, 0.003);
}

TEST(NormalBoundsTree, IntegratesToOneOverTheDisk) {
    // ∫ D dA over the disk by the 4 × 4 means of 128² pixels on a rough surface, for a Gaussian
    // footprint and the whole field: a quadrature across the caustics (measured 1.0030 and
    // 0.9985); a wrong scale of D (pixel units, the truncation) would be far outside.
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(64));
    const int n = 64;
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, {}, n);
    Footprint whole;
    whole.shape = FootprintShape::whole;
    for (const Footprint& footprint : {gaussian_at({10.0, 20.0}, 6.0), whole}) {
        const int pixels = 128;
        double total = 0.0;
        for (double mean : pixel_means(tree, footprint, pixels, 4)) total += mean;
        total *= disk_pixel_area(pixels);
        RecordProperty(footprint.shape == FootprintShape::whole ? "whole" : "gaussian", ::testing::PrintToString(total));
        EXPECT_NEAR(total, 1.0, 5e-3);
    }
}

TEST(NormalBoundsTree, TiltedPlaneSitsAtItsNormal) {
    // Every triangle's image is the plane's normal m0: without roughness D is zero everywhere
    // else; with roughness σ it is the Gaussian exp(−|h − m0|²/2σ²)/(2πσ²) of the disk.
    const double sx = 0.3, sy = -0.2;
    const auto surface = std::make_shared<const BicubicInterpolant>(sampled_field(64, 64, 1.0, [&](double x, double y) { return sx * x + sy * y; }));
    const double norm = std::sqrt(1.0 + sx * sx + sy * sy);
    const DiskPoint m0{-sx / norm, -sy / norm};
    const Footprint footprint = gaussian_at({32.0, 32.0}, 4.0);  // inside the tile, away from the wrap
    const NormalBoundsTree sharp = make_normal_bounds_tree(surface, {}, 64);
    for (const DiskPoint h : {DiskPoint{m0.x + 0.02, m0.y}, DiskPoint{0.0, 0.0}, DiskPoint{m0.x, m0.y - 0.1}})
        EXPECT_EQ(point_normal_density(sharp, footprint, h), 0.0);
    const double sigma = 0.05;
    const NormalBoundsTree rough = make_normal_bounds_tree(surface, {1, 0.02, sigma}, 64);
    for (const DiskPoint h : {m0, DiskPoint{m0.x + 0.03, m0.y}, DiskPoint{m0.x - 0.05, m0.y + 0.08}}) {
        const double r2 = (h.x - m0.x) * (h.x - m0.x) + (h.y - m0.y) * (h.y - m0.y);
        const double expected = std::exp(-0.5 * r2 / (sigma * sigma)) / (2.0 * std::numbers::pi * sigma * sigma);
        EXPECT_NEAR(point_normal_density(rough, footprint, h), expected, 1e-6 * expected);
    }
}

TEST(NormalBoundsTree, PruningNeverChangesTheResult) {
    // Subdivided cells (the adaptive tolerance at N = 64 divides many texels of this surface),
    // a Gaussian, an elliptical one, the whole field and a rotated box straddling the field's edge,
    // with and without roughness: the pruned query skips only
    // zeros, so it is the brute-force sum over every triangle of the support, bit for bit.
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(64));
    Footprint whole;
    whole.shape = FootprintShape::whole;
    for (double roughness : {0.0, 0.03}) {
        const NormalBoundsTree tree = make_normal_bounds_tree(surface, {1, 0.02, roughness}, 64);
        ASSERT_GT(*std::max_element(tree.subdivision.begin(), tree.subdivision.end()), 1);
        int nonzero = 0;
        for (const Footprint& footprint : {gaussian_at({5.0, 60.0}, 7.0), ellipse_at({5.0, 60.0}, 9.0, 4.0, 2.0), whole,
                                           box_at({5.0, 60.0}, 21.0, 13.0, 0.7)})
            for (int k = 0; k < 100; ++k) {
                const DiskPoint h{0.3 * std::cos(0.7 * k) * (k % 17) / 17.0, 0.3 * std::sin(0.7 * k) * (k % 13) / 13.0};
                const double pruned = point_normal_density(tree, footprint, h, Pruning::on);
                EXPECT_EQ(pruned, point_normal_density(tree, footprint, h, Pruning::off)) << k;
                nonzero += pruned > 0.0;
            }
        EXPECT_GT(nonzero, 50) << "the points miss the distribution";
    }
}

TEST(NormalBoundsTree, ManyThreadsGiveTheSameAnswers) {
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(64));
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, {}, 64);
    constexpr int kQueries = 4000;
    const auto query = [&](int k) {
        return point_normal_density(tree, gaussian_at({0.5 * k, 0.25 * k}, 5.0), {0.2 * std::cos(k), 0.2 * std::sin(1.3 * k)});
    };
    std::vector<double> serial(kQueries), threaded(kQueries);
    for (int k = 0; k < kQueries; ++k) serial[k] = query(k);
    std::vector<std::thread> pool;
    for (int t = 0; t < 8; ++t)
        pool.emplace_back([&, t] {
            for (int k = t; k < kQueries; k += 8) threaded[k] = query(k);
        });
    for (std::thread& thread : pool) thread.join();
    EXPECT_EQ(serial, threaded);
}

TEST(NormalBoundsTree, StraddlingFootprintEqualsTheShiftedFields) {
    // A footprint on the field's corner reads the four tiles around it: the field shifted by half
    // a period, with the footprint at its centre, holds the same surface there.
    const Heightfield field = isotropic_field(64);
    Heightfield shifted = field;
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) shifted.at((r + 32) % 64, (c + 32) % 64) = field.at(r, c);
    const NormalBoundsTree tree = make_normal_bounds_tree(std::make_shared<const BicubicInterpolant>(field), {}, 64);
    const NormalBoundsTree shifted_tree = make_normal_bounds_tree(std::make_shared<const BicubicInterpolant>(shifted), {}, 64);
    int nonzero = 0;
    for (int k = 0; k < 300; ++k) {
        const DiskPoint h{0.25 * std::cos(0.9 * k) * (k % 11) / 11.0, 0.25 * std::sin(0.9 * k) * (k % 7) / 7.0};
        const double corner = point_normal_density(tree, gaussian_at({0.0, 0.0}, 6.0), h);
        const double centre = point_normal_density(shifted_tree, gaussian_at({32.0, 32.0}, 6.0), h);
        EXPECT_NEAR(corner, centre, 1e-9 * centre) << k;
        nonzero += corner > 0.0;
    }
    EXPECT_GT(nonzero, 150);
}

TEST(NormalBoundsTree, IntrinsicRoughnessMatchesTheBlurredImage) {
    // The image blurs its pixels (4σ kernel, mass past the rim restored); the query blurs each
    // triangle by the edge-midpoint rule. Measured relative L2 of the 2 × 2 pixel means: 4.3e-3
    // at σ = 0.08 (1.9 pixels; 5.2e-3 at the pixel centres, tested); at σ = 0.04 (1 pixel) 0.018, where
    // the image's point-sampled kernel is itself coarse.
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(64));
    const Footprint footprint = gaussian_at({30.0, 20.0}, 6.0);
    const NormalDensitySettings settings{1, 0.02, 0.08};
    const int n = 48;
    const std::vector<double> image = normal_density(*surface, footprint, n, settings);
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, settings, n);
    const double error = relative_l2(pixel_means(tree, footprint, n, 1), image);
    RecordProperty("relative_l2", ::testing::PrintToString(error));
    EXPECT_LT(error, 0.01);
}

TEST(NormalBoundsTree, SampledNormalsFallInTheImagesPixelsWithTheirMass) {
    // The sampler draws the point query's triangles by weight and a uniform point of each image:
    // the probability of an image pixel is then its exact coverage, the image's pixel mass
    // D (2/N)² (both renormalised: the image by its sum, the sampler by the triangles' weight).
    // χ² of 10⁶ draws over the N² pixels on a rough surface with folds, adaptive subdivision;
    // and the density the sampler reports is the point query's D times what its weights sum to.
    // For a circle and an ellipse (whose cells' weights are summed triangle by triangle).
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(96));
    const int n = 32;
    const NormalDensitySettings settings;
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, settings, n);
    for (const Footprint& footprint : {gaussian_at({40.0, 50.0}, 8.0), ellipse_at({40.0, 50.0}, 11.0, 5.0, 0.7)}) {
        SCOPED_TRACE(is_elliptical(footprint) ? "ellipse" : "circle");
        const std::vector<double> image = normal_density(*surface, footprint, n, settings);
        const NormalSampler sampler = make_normal_sampler(tree, footprint);
        const testing::DiskChiSquare chi_square{n, 1'000'000};
        const CounterRng rng(23, 1);
        const std::vector<long> observed = chi_square.histogram(testing::Grid::omega_o, {0.0, 0.0, 1.0}, [&](long k) -> std::optional<Vec3> {
            const std::optional<DiskPoint> h = sample_normal(tree, sampler, rng.uniform(2 * k), rng.uniform(2 * k + 1));
            if (!h) return std::nullopt;
            return direction_from_disk(h->x, h->y);
        });
        std::vector<double> expected(image.size() + 1, 0.0);
        for (std::size_t k = 0; k < image.size(); ++k) expected[k] = image[k] * disk_pixel_area(n);
        const double p = chi_square.p_value(observed, expected);
        RecordProperty("p_value", ::testing::PrintToString(p));
        EXPECT_GT(p, 0.01);
        for (int k = 0; k < 50; ++k) {
            const DiskPoint h{0.3 * std::cos(0.7 * k), 0.3 * std::sin(1.1 * k)};
            EXPECT_NEAR(sampled_normal_density(tree, sampler, h), point_normal_density(tree, footprint, h), 1e-4 * point_normal_density(tree, footprint, h));
        }
    }
}

TEST(NormalBoundsTree, BadSettingsAreRefused) {
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(32));
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, {}, 32);
    EXPECT_THROW(make_normal_sampler(make_normal_bounds_tree(surface, {1, 0.02, 0.05}, 32), gaussian_at({1.0, 2.0}, 5.0)), Error);
    EXPECT_THROW(make_normal_bounds_tree(surface, {0, 0.02, 0.0}, 32), Error);
    EXPECT_THROW(make_normal_bounds_tree(surface, {1, 0.02, NAN}, 32), Error);
}

TEST(NormalBoundsTree, BoxesTilingARotatedBoxPartitionItsDensity) {
    // The preimage rule puts each triangle's point s(h) in exactly one of k × k boxes that tile a
    // big one (translated by its edge vectors over k), so Σ area_k D_k(h) = area D(h): the same
    // triangles' terms summed in other groups, to rounding. On a rough surface (folds: many
    // triangles hold h), adaptive subdivision; with roughness the centroid rule partitions alike.
    // Measured: largest relative difference 2.9e-16 (8.1e-16 with roughness).
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(64));
    const double width = 24.0, height = 15.0, axis = 0.4;
    const Point2 centre{30.0, 34.0}, along{std::cos(axis), std::sin(axis)}, across{-std::sin(axis), std::cos(axis)};
    const int k = 3;
    for (double roughness : {0.0, 0.03}) {
        const NormalBoundsTree tree = make_normal_bounds_tree(surface, {1, 0.02, roughness}, 64);
        double worst = 0.0;
        int nonzero = 0;
        for (int q = 0; q < 100; ++q) {
            const DiskPoint h{0.3 * std::cos(0.7 * q) * (q % 17) / 17.0, 0.3 * std::sin(0.7 * q) * (q % 13) / 13.0};
            const double whole = width * height * point_normal_density(tree, box_at(centre, width, height, axis), h);
            double parts = 0.0;
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) {
                    const double u = (i + 0.5 - 0.5 * k) * width / k, v = (j + 0.5 - 0.5 * k) * height / k;
                    const Point2 part{centre.x + u * along.x + v * across.x, centre.y + u * along.y + v * across.y};
                    parts += width * height / (k * k) * point_normal_density(tree, box_at(part, width / k, height / k, axis), h);
                }
            EXPECT_NEAR(parts, whole, 1e-12 * whole) << q;
            if (whole > 0.0) worst = std::max(worst, std::abs(parts - whole) / whole), ++nonzero;
        }
        RecordProperty(roughness > 0.0 ? "worst_rough" : "worst", ::testing::PrintToString(worst));
        EXPECT_GT(nonzero, 50) << "the points miss the distribution";
    }
}

TEST(NormalBoundsTree, ARotatedBoxOnAParaboloidIsItsPreimagesClosedForm) {
    // H = |s − o|²/(2R): the normal's disk point is m(s) = −g/√(1 + |g|²), g = (s − o)/R, with
    // |det ∂m/∂s| = 1/(R² (1 + |g|²)²), so a box's D(h) is R² (1 + |g|²)²/(W·H) where h's
    // preimage s = o − R h/√(1 − |h|²) lies in the box and 0 where it does not. The triangle
    // model holds each triangle's image density constant and its corners' normals exact (the
    // bicubic reproduces a quadratic): measured largest relative error 7.8e-4 over points half a
    // texel or more inside (|g| < 0.16), exactly 0 outside.
    const double radius = 200.0;
    const Point2 origin{64.0, 64.0}, centre{70.0, 58.0};
    const double width = 30.0, height = 18.0, axis = 0.6;
    const NormalBoundsTree tree = make_normal_bounds_tree(quadratic_surface(1.0 / radius, 1.0 / radius, 0.0, origin), {1, 0.0, 0.0}, 64);
    const Footprint box = box_at(centre, width, height, axis);
    double worst = 0.0;
    int inside = 0, outside = 0;
    for (int b = -12; b <= 12; ++b)
        for (int a = -12; a <= 12; ++a) {
            const double u = a / 10.0 * 0.5 * width, v = b / 10.0 * 0.5 * height;  // reaching 1.2 half sides
            const Point2 s{centre.x + u * std::cos(axis) - v * std::sin(axis), centre.y + u * std::sin(axis) + v * std::cos(axis)};
            const double gx = (s.x - origin.x) / radius, gy = (s.y - origin.y) / radius, g2 = gx * gx + gy * gy;
            const DiskPoint h{-gx / std::sqrt(1.0 + g2), -gy / std::sqrt(1.0 + g2)};
            const double measured = point_normal_density(tree, box, h);
            if (std::abs(u) < 0.5 * width - 0.5 && std::abs(v) < 0.5 * height - 0.5) {
                const double expected = radius * radius * (1.0 + g2) * (1.0 + g2) / (width * height);
                worst = std::max(worst, std::abs(measured - expected) / expected);
                ++inside;
            } else if (std::abs(u) > 0.5 * width + 0.5 || std::abs(v) > 0.5 * height + 0.5) {
                EXPECT_EQ(measured, 0.0) << a << "," << b;
                ++outside;
            }
        }
    RecordProperty("worst_relative_error", ::testing::PrintToString(worst));
    EXPECT_LT(worst, 2e-3);
    EXPECT_GT(inside, 300);
    EXPECT_GT(outside, 100);
}

TEST(NormalBoundsTree, ABoxTurnedByAQuarterWithSwappedSidesIsTheSameBox) {
    // The same rectangle: its triangles, their points and the sums alike (1e-12; the lattice of
    // the turned box's bounding rectangle may hold a row more, whose terms are 0).
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(64));
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, {}, 64);
    int nonzero = 0;
    for (int k = 0; k < 60; ++k) {
        const DiskPoint h{0.3 * std::cos(0.9 * k) * (k % 7) / 7.0, 0.3 * std::sin(0.9 * k) * (k % 5) / 5.0};
        const double straight = point_normal_density(tree, box_at({20.0, 30.0}, 20.0, 12.0, 0.0), h);
        const double turned = point_normal_density(tree, box_at({20.0, 30.0}, 12.0, 20.0, 0.5 * pi), h);
        EXPECT_NEAR(turned, straight, 1e-12 * straight) << k;
        nonzero += straight > 0.0;
    }
    EXPECT_GT(nonzero, 30);
}

TEST(NormalBoundsTree, AnAxisAlignedBoxsPointValuesMatchItsImage) {
    // The image's box lattice follows the box's edges (its triangles differ from the texels'),
    // and its pixels are exact shares where the query is a point value: they differ where D
    // steps, along the box's image's edge. Measured on a quadratic patch, a 30 × 20 µm box
    // (about 19 × 11 pixels of N = 64): relative L2 0.18 at the pixel centres (the edge's pixels:
    // far from the conformance suite's 1e-4, so make_bsdf answers an axis-aligned box from the
    // image), 0.016 for the 4 × 4 means; and ∫ D dA over the disk by the 4 × 4 means of 128²
    // pixels is 1.00045 (a quadrature across the edge; the preimage rule holds the box's mass).
    const auto surface = quadratic_surface(0.02, 0.015, 0.005, {64.0, 64.0});
    const Footprint box = box_at({61.3, 66.8}, 30.0, 20.0, 0.0);
    const ImageAgreement agreement = agreement_with_image(surface, box);
    EXPECT_LT(agreement.centres, 0.25);
    EXPECT_LT(agreement.means, 0.025);
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, {1, 0.0, 0.0}, 64);
    double total = 0.0;
    for (double mean : pixel_means(tree, box, 128, 4)) total += mean;
    total *= disk_pixel_area(128);
    RecordProperty("integral", ::testing::PrintToString(total));
    EXPECT_NEAR(total, 1.0, 1e-3);
}

TEST(NormalBoundsTree, RotatedBoxSamplesFollowTheQueriedDensity) {
    // A box's sampler weighs each triangle by its area inside the box and draws uniformly over
    // that part's image: its density is the query's D (density_scale 1 but for rounding) and
    // its draws follow it. χ² of 5·10⁴ draws over 20 × 20 cells of the disk against D integrated
    // by 32 × 32 points per cell (DiskChiSquare), on a quadratic patch with a rotated box.
    // Measured: density_scale − 1 = −8e-15, ∫ D dA − 1 = −8.8e-5 (the cells' quadrature across the
    // box's image's edge), p = 0.23.
    const auto surface = quadratic_surface(0.02, 0.015, 0.005, {64.0, 64.0});
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, {1, 0.0, 0.0}, 64);
    const Footprint box = box_at({61.3, 66.8}, 30.0, 20.0, 0.5);
    const NormalSampler sampler = make_normal_sampler(tree, box);
    RecordProperty("density_scale_minus_1", ::testing::PrintToString(sampler.density_scale - 1.0));
    EXPECT_NEAR(sampler.density_scale, 1.0, 1e-12);
    const testing::DiskChiSquare chi_square{20, 50'000};
    const CounterRng rng(23, 2);
    int checked = 0;
    const std::vector<long> observed = chi_square.histogram(testing::Grid::omega_o, {0.0, 0.0, 1.0}, [&](long k) -> std::optional<Vec3> {
        const std::optional<DiskPoint> h = sample_normal(tree, sampler, rng.uniform(2 * k), rng.uniform(2 * k + 1));
        if (!h) return std::nullopt;
        if (k % 100 == 0) {
            EXPECT_GT(point_normal_density(tree, box, *h), 0.0) << "a draw where the query has no density";
            ++checked;
        }
        return direction_from_disk(h->x, h->y);
    });
    EXPECT_GT(checked, 400);
    std::vector<double> expected(20 * 20 + 1, 0.0);
    chi_square.disk_probabilities([&](Vec3 h) { return sampled_normal_density(tree, sampler, {h.x, h.y}) * h.z; }, 32, expected);
    const double p = chi_square.p_value(observed, expected);  // which also checks ∫ pdf = 1 (1e-3)
    RecordProperty("p_value", ::testing::PrintToString(p));
    EXPECT_GT(p, 0.01);
}

}  // namespace
}  // namespace glintscope
