// The point query of the exact normal density against its image: the image's pixel is the mean
// of the point query over the pixel, point values at pixel centres match a smooth surface's
// image, also for an elliptical footprint (whose D on a sphere cap is its Gaussian), ∫ D dA = 1, a tilted plane's D sits at its normal, pruning changes nothing, threads
// change nothing, a footprint straddling the field's edge reads the tiles on both sides,
// intrinsic roughness matches the image's blur, and the sampler's draws of h fall in the image's
// pixels with their masses.
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

TEST(NormalBoundsTree, PointValuesAtPixelCentresMatchASmoothSurfacesImage) {
    // A paraboloid patch (a Gaussian in slope space, normal_density_test.cpp): D is smooth but
    // for the steps between neighbouring triangles' centroid weights (about texel/σ_w of the
    // weight), which a pixel's mean smooths out. Measured relative L2 at N = 64, σ_c = 20 µm:
    // 0.018 at the pixel centres, 0.0021 for the 4 × 4 means (σ_c = 10 µm: 0.049 and 0.0060).
    const double a = 0.008, b = 0.006, c = 0.002;
    const Point2 origin{58.0, 70.0};
    const auto surface = std::make_shared<const BicubicInterpolant>(sampled_field(128, 128, 1.0, [&](double x, double y) {
        const double u = x - origin.x, v = y - origin.y;
        return 0.5 * a * u * u + 0.5 * b * v * v + c * u * v;
    }));
    const Footprint footprint = gaussian_at({64.0, 64.0}, 20.0);
    const int n = 64;
    const NormalDensitySettings undivided{1, 0.0, 0.0};  // the field's seam would be divided 64-fold
    const std::vector<double> image = normal_density(*surface, footprint, n, undivided);
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, undivided, n);
    const double at_centres = relative_l2(pixel_means(tree, footprint, n, 1), image);
    const double means = relative_l2(pixel_means(tree, footprint, n, 4), image);
    RecordProperty("relative_l2_centres", ::testing::PrintToString(at_centres));
    RecordProperty("relative_l2_k4", ::testing::PrintToString(means));
    EXPECT_LT(at_centres, 0.025);
    EXPECT_LT(means, 0.003);
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
    // a Gaussian, an elliptical one and the whole field, with and without roughness: the pruned query skips only
    // zeros, so it is the brute-force sum over every triangle of the support, bit for bit.
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(64));
    Footprint whole;
    whole.shape = FootprintShape::whole;
    for (double roughness : {0.0, 0.03}) {
        const NormalBoundsTree tree = make_normal_bounds_tree(surface, {1, 0.02, roughness}, 64);
        ASSERT_GT(*std::max_element(tree.subdivision.begin(), tree.subdivision.end()), 1);
        int nonzero = 0;
        for (const Footprint& footprint : {gaussian_at({5.0, 60.0}, 7.0), ellipse_at({5.0, 60.0}, 9.0, 4.0, 2.0), whole})
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

TEST(NormalBoundsTree, BoxFootprintsAndBadSettingsAreRefused) {
    const auto surface = std::make_shared<const BicubicInterpolant>(isotropic_field(32));
    const NormalBoundsTree tree = make_normal_bounds_tree(surface, {}, 32);
    Footprint box;
    box.shape = FootprintShape::box;
    box.size_um = 10.0;
    EXPECT_THROW(point_normal_density(tree, box, {0.0, 0.0}), Error);
    EXPECT_THROW(make_normal_sampler(tree, box), Error);
    EXPECT_THROW(make_normal_sampler(make_normal_bounds_tree(surface, {1, 0.02, 0.05}, 32), gaussian_at({1.0, 2.0}, 5.0)), Error);
    EXPECT_THROW(make_normal_bounds_tree(surface, {0, 0.02, 0.0}, 32), Error);
    EXPECT_THROW(make_normal_bounds_tree(surface, {1, 0.02, NAN}, 32), Error);
}

}  // namespace
}  // namespace glintscope
