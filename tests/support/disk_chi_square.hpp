#pragma once
// A χ² test of a sampler of directions against its pdf over the projected disk, as pbrt-v4 tests
// its BxDFs (bsdfs_test.cpp): shared by the BSDF conformance suite and the methods' own samplers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "glintscope/core/geometry.hpp"
#include "numerics/disk_distribution.hpp"

namespace glintscope::testing {

// Where samples are counted: half-pixel cells of the projected disk of ω_o, on which a sampler
// over the images has a constant density, or of the half vector h = (ω_i + ω_o)/|ω_i + ω_o| for
// a method's own sampler, which draws h from a table of the NDF (Walter 2007): its density is
// constant over the table's pixels, whose sides (2/(2N), 2/(4N)) the cells' sides divide, so the
// expected counts are exact in either case. h ↦ ω_o is one to one, so either is a test of the
// whole distribution.
enum class Grid { omega_o, half_vector };

// Histogram cells: `cells` × `cells` squares over [−1, 1]², and `samples` drawn.
struct DiskChiSquare {
    int cells;
    long samples;

    int cell_of(Grid grid, Vec3 omega_i, Vec3 omega_o) const {
        const Vec3 w = grid == Grid::omega_o ? omega_o : normalize(omega_i + omega_o);
        const int col = std::clamp(static_cast<int>((w.x + 1.0) * 0.5 * cells), 0, cells - 1);
        const int row = std::clamp(static_cast<int>((1.0 - w.y) * 0.5 * cells), 0, cells - 1);
        return row * cells + col;
    }

    // The counts of `samples` draws in the cells, draw(k) giving the k-th ω_o or none (the last
    // cell counts those).
    template <typename Draw>
    std::vector<long> histogram(Grid grid, Vec3 omega_i, const Draw& draw) const {
        std::vector<long> observed(cells * cells + 1, 0);
        for (long k = 0; k < samples; ++k) {
            const auto omega_o = draw(k);
            ++observed[omega_o ? cell_of(grid, omega_i, *omega_o) : observed.size() - 1];
        }
        return observed;
    }

    // The probability of each disk cell: the density per disk area (pdf / cosθ) averaged over
    // points × points points of the cell that lie inside the disk, times the cell's area inside the disk. Near
    // grazing a lobe may put much of its mass in the rim's slivers (G = 1 and 1/cosθ_o), so a sliver
    // that holds none of the points is read at its point nearest the disk's centre.
    template <typename Pdf>
    void disk_probabilities(const Pdf& pdf, int points, std::vector<double>& expected) const {
        const double side = 2.0 / cells;
        for (int row = 0; row < cells; ++row)
            for (int col = 0; col < cells; ++col) {
                const double x0 = -1.0 + col * side, y1 = 1.0 - row * side;
                const double area = area_inside_disk(x0, x0 + side, y1 - side, y1);
                if (area <= 0.0) continue;
                double sum = 0.0;
                int inside = 0;
                for (int a = 0; a < points; ++a)
                    for (int b = 0; b < points; ++b) {
                        const DiskPoint p{x0 + (a + 0.5) * side / points, y1 - (b + 0.5) * side / points};
                        if (!inside_unit_disk(p)) continue;
                        const Vec3 omega = direction_from_disk(p.x, p.y);
                        sum += pdf(omega) / omega.z;
                        ++inside;
                    }
                if (inside == 0) {
                    const double x = std::clamp(0.0, x0, x0 + side), y = std::clamp(0.0, y1 - side, y1);
                    const double shrink = (1.0 - 1e-9) / std::hypot(x, y);
                    const Vec3 omega = direction_from_disk(x * shrink, y * shrink);
                    sum = pdf(omega) / omega.z;
                    inside = 1;
                }
                expected[row * cells + col] = sum / inside * area;
            }
    }

    // The probability of every cell, and a last entry for samples that find no direction. Over h,
    // the density per solid angle of h is pdf(ω_o) · 4 ω_o·h (Walter 2007 eq. 14).
    template <typename Pdf>
    std::vector<double> expected_probabilities(Grid grid, Vec3 omega_i, const Pdf& pdf) const {
        std::vector<double> expected(cells * cells + 1, 0.0);
        if (grid == Grid::omega_o) {
            disk_probabilities(pdf, 4, expected);
            return expected;
        }
        disk_probabilities(
            [&](Vec3 h) {
                const double cos_ih = dot(omega_i, h);
                const Vec3 omega_o = 2.0 * cos_ih * h - omega_i;
                return cos_ih > 0.0 && omega_o.z > 0.0 ? pdf(omega_o) * 4.0 * cos_ih : 0.0;
            },
            16, expected);  // the horizon of ω_o cuts the cells of h along a curve: 16 × 16 points
        return expected;
    }

    // Upper tail of χ² with k degrees of freedom (Wilson–Hilferty: k is in the hundreds here).
    static double chi_square_tail(double statistic, double dof) {
        const double c = 2.0 / (9.0 * dof);
        const double z = (std::cbrt(statistic / dof) - (1.0 - c)) / std::sqrt(c);
        return 0.5 * std::erfc(z / std::sqrt(2.0));
    }

    // Pearson's statistic of the observed counts against the expected probabilities, cells with
    // an expected count below 5 pooled into one; returns the p-value. The last cell counts the
    // samples that found no direction (a microfacet sampler's h that reflects ω_i below the
    // horizon): the pdf over the disk must integrate to 1 less their share, to 1e-3 beyond the
    // share's own 3σ (a sampler over the images never fails: the pdf integrates to 1).
    double p_value(std::vector<long> observed, std::vector<double> expected) const {
        double total = 0.0;
        for (double e : expected) total += e;
        const double failed = double(observed.back()) / samples;
        EXPECT_NEAR(total, 1.0 - failed, 1e-3 + 3.0 * std::sqrt(failed * (1.0 - failed) / samples))
            << "the pdf does not integrate to 1 less the failed samples' share";
        expected.back() = std::max(0.0, 1.0 - total);
        double statistic = 0.0, pooled_expected = 0.0;
        long pooled_observed = 0;
        int counted = 0;
        for (std::size_t i = 0; i < expected.size(); ++i) {
            const double e = expected[i] * samples;
            if (e < 5.0) {
                pooled_expected += e;
                pooled_observed += observed[i];
                continue;
            }
            statistic += (observed[i] - e) * (observed[i] - e) / e;
            ++counted;
        }
        if (pooled_expected > 0.0) {
            // A pool that expects nothing must receive nothing.
            if (pooled_expected < 5.0) {
                EXPECT_LE(pooled_observed, 5 + 5 * pooled_expected) << "samples where the pdf is ~0";
            } else {
                statistic += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected;
                ++counted;
            }
        }
        return counted > 1 ? chi_square_tail(statistic, counted - 1) : 1.0;
    }
};

inline double sidak_significance(int tests) { return 1.0 - std::pow(1.0 - 0.01, 1.0 / tests); }


}  // namespace glintscope::testing
