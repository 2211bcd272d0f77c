// Yan 2018 eq. 6 at single directions over the fft image's own footprint grid (fft_lobe.hpp).
#include <cmath>
#include <complex>
#include <cstring>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "fft_lobe.hpp"
#include "row_spectra.hpp"
#include "glintscope/lobe/image.hpp"
#include "glintscope/optics/material.hpp"

// The SIMD helper takes and returns no vector types across calls; -Wpsabi's note does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace glintscope {
namespace {

// One incidence's grid for one wavelength. At constant ξ3 = 2 (OHS, R-OHS) R*(s) =
// w e^{−i2π ξ3 (H − H̄)/λ} (Yan 2018 eq. 1, 4) is the same for every direction: its rows are kept
// as their oversampled spectra, each direction reading 17 bins per row instead of every sample,
// and of the samples only the axes are kept. Otherwise (ξ3 = ψ·n) the samples, R* made per
// direction.
struct IncidenceGrid {
    FootprintSamples samples;
    RowSpectra spectra;  // OHS, R-OHS
};

// e^{−i2π f (j·step)} for j < count, as real and imaginary parts, without a sincos per sample:
// one every kPhasorBlock samples, the others that one times the block's powers of e^{−i2π f step}
// (a rounding of a few 1e-16 each, where the 1e-4 agreement with the image needs 1e-9).
constexpr int kPhasorBlock = 32;

void plane_wave(double frequency, double step_um, int count, std::vector<double>& re, std::vector<double>& im) {
    re.resize(count);
    im.resize(count);
    std::complex<double> powers[kPhasorBlock];
    for (int m = 0; m < kPhasorBlock; ++m) powers[m] = std::polar(1.0, -2.0 * pi * frequency * (m * step_um));
    for (int first = 0; first < count; first += kPhasorBlock) {
        const std::complex<double> anchor = std::polar(1.0, -2.0 * pi * frequency * (first * step_um));
        for (int m = 0; m < kPhasorBlock && first + m < count; ++m) {
            const std::complex<double> e = m == 0 ? anchor : anchor * powers[m];
            re[first + m] = e.real();
            im[first + m] = e.imag();
        }
    }
}

using Double4 = double __attribute__((vector_size(32)));

inline __attribute__((always_inline)) Double4 load4(const double* p) {
    Double4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

// Σ_j (factor_j) r_j e_j of one grid row, r = R*, e the plane wave along x, factor a slope or 1
// (null): four samples per SIMD step, alternate steps into two sums so that consecutive steps do
// not wait for each other's additions, added in a fixed order, the rest one by one.
__attribute__((target_clones("arch=x86-64-v3", "default")))
std::complex<double> row_sum(const double* r_re, const double* r_im, const double* e_re, const double* e_im,
                             const double* factor, int n) {
    Double4 re0 = {}, im0 = {}, re1 = {}, im1 = {};
    const auto step = [&](int i, Double4& re4, Double4& im4) {
        const Double4 a = load4(r_re + i), b = load4(r_im + i), d = load4(e_re + i), e = load4(e_im + i);
        const Double4 f = factor ? load4(factor + i) : Double4{1.0, 1.0, 1.0, 1.0};
        re4 += f * (a * d - b * e);
        im4 += f * (a * e + b * d);
    };
    int j = 0;
    for (; j + 8 <= n; j += 8) {
        step(j, re0, im0);
        step(j + 4, re1, im1);
    }
    if (j + 4 <= n) {
        step(j, re0, im0);
        j += 4;
    }
    const Double4 re_all = re0 + re1, im_all = im0 + im1;
    double re = 0.0, im = 0.0;
    for (; j < n; ++j) {
        const double f = factor ? factor[j] : 1.0;
        re += f * (r_re[j] * e_re[j] - r_im[j] * e_im[j]);
        im += f * (r_re[j] * e_im[j] + r_im[j] * e_re[j]);
    }
    return {((re_all[0] + re_all[1]) + (re_all[2] + re_all[3])) + re, ((im_all[0] + im_all[1]) + (im_all[2] + im_all[3])) + im};
}

class FftPoint {
public:
    explicit FftPoint(const LobeQuery& query)
        : query_(query), area_um2_(footprint_extent(query.footprint, fft_settings(query).window_sigmas).area_um2) {
        for (double lambda : query_.wavelengths_um)
            indices_.push_back(query_.material.name.empty() ? ComplexIndex{}
                                                            : complex_refractive_index(query_.material.name, lambda));
    }

    std::vector<double> eval(Vec3 omega_i, Vec3 omega_o) const {
        const Vec3 psi = omega_i + omega_o;
        const double xi3 = phase_depends_on_outgoing(query_.model) ? psi.z : 2.0;  // Yan 2018 Fig. 6: ψ·n or 2
        std::vector<double> f;
        for (std::size_t layer = 0; layer < query_.wavelengths_um.size(); ++layer) {
            const double lambda = query_.wavelengths_um[layer];
            const std::shared_ptr<const IncidenceGrid> grid = grid_for(omega_i, layer);
            const FootprintSamples& s = grid->samples;
            const double cell = s.x.step_um * s.y.step_um;
            const double fresnel = query_.material.name.empty() ? 1.0 : fresnel_conductor(indices_[layer], 0.5 * length(psi));
            // Yan 2018 eq. 6: ξ1/A_c |R̃*(ψ̄/λ)|², R̃* the grid's sum times its cell area.
            const double factor = xi1_geometric(query_.model, omega_i, omega_o) * fresnel / (lambda * lambda);
            f.push_back(factor * std::norm(transform(*grid, psi, xi3, lambda)) * cell * cell / area_um2_);
        }
        return f;
    }

private:
    // Σ_s R*(s) e^{−i2π ψ̄·s/λ} over the grid (s from its first sample); Kirchhoff's ξ2 as in the
    // image: T0 − (ψ̄_x T_x + ψ̄_y T_y)/(ψ·n), T_x and T_y the sums of H_x R* and H_y R*.
    std::complex<double> transform(const IncidenceGrid& grid, Vec3 psi, double xi3, double lambda) const {
        if (!grid.spectra.re.empty()) return transform_of_spectra(grid, psi, lambda);
        const FootprintSamples& s = grid.samples;
        const int nx = s.x.count, ny = s.y.count;
        const bool kirchhoff = query_.model == DiffractionModel::kirchhoff;
        std::vector<double> wave_re, wave_im, column_re, column_im, row_re(nx), row_im(nx);
        plane_wave(psi.x / lambda, s.x.step_um, nx, wave_re, wave_im);
        plane_wave(psi.y / lambda, s.y.step_um, ny, column_re, column_im);
        const double phase_per_height = -2.0 * pi * xi3 / lambda;
        std::complex<double> sums[3];
        for (int k = 0; k < ny; ++k) {
            const std::size_t first = static_cast<std::size_t>(k) * nx;
            for (int j = 0; j < nx; ++j) {
                const double angle = phase_per_height * s.height[first + j];
                row_re[j] = s.weight[first + j] * std::cos(angle);
                row_im[j] = s.weight[first + j] * std::sin(angle);
            }
            const double *r_re = row_re.data(), *r_im = row_im.data();
            const std::complex<double> row_wave(column_re[k], column_im[k]);
            sums[0] += row_wave * row_sum(r_re, r_im, wave_re.data(), wave_im.data(), nullptr, nx);
            if (kirchhoff) {
                sums[1] += row_wave * row_sum(r_re, r_im, wave_re.data(), wave_im.data(), &s.slope_x[first], nx);
                sums[2] += row_wave * row_sum(r_re, r_im, wave_re.data(), wave_im.data(), &s.slope_y[first], nx);
            }
        }
        return kirchhoff ? sums[0] - (psi.x * sums[1] + psi.y * sums[2]) / psi.z : sums[0];
    }

    // The same sum from the rows' spectra: Σ_k e^{−i2π ψ̄_y y_k/λ} S_k(ψ̄_x h_x/λ), S_k the
    // transform of row k (row_spectra.hpp), read as Σ over its taps of weight · (that bin of every
    // row, summed against the column's plane wave).
    static std::complex<double> transform_of_spectra(const IncidenceGrid& grid, Vec3 psi, double lambda) {
        const FootprintSamples& s = grid.samples;
        const RowSpectra& spectra = grid.spectra;
        std::vector<double> column_re, column_im;
        plane_wave(psi.y / lambda, s.y.step_um, s.y.count, column_re, column_im);
        const SpectrumTaps taps = spectrum_taps(spectra, psi.x / lambda * s.x.step_um);
        std::complex<double> sum;
        for (int i = 0; i < taps.count; ++i) {
            const std::size_t first = static_cast<std::size_t>(taps.bin[i]) * spectra.rows;
            sum += taps.weight[i] *
                   row_sum(&spectra.re[first], &spectra.im[first], column_re.data(), column_im.data(), nullptr, spectra.rows);
        }
        return taps.phase * sum;
    }

    // The grid of (ω_i, wavelength), made on first use outside the lock (two threads may both
    // make it, identically); the most recent are kept.
    std::shared_ptr<const IncidenceGrid> grid_for(Vec3 omega_i, std::size_t layer) const {
        {
            const std::lock_guard lock(mutex_);
            for (const Entry& e : recent_)
                if (e.layer == layer && e.omega_i.x == omega_i.x && e.omega_i.y == omega_i.y && e.omega_i.z == omega_i.z)
                    return e.grid;
        }
        const double lambda = query_.wavelengths_um[layer];
        auto grid = std::make_shared<IncidenceGrid>();
        grid->samples = layer_samples(query_, {omega_i, 1.0}, lambda);
        if (!phase_depends_on_outgoing(query_.model)) {
            FootprintSamples& s = grid->samples;
            const double phase_per_height = -2.0 * pi * 2.0 / lambda;
            grid->spectra = row_spectra(s.x.count, s.y.count, [&](std::size_t k, std::complex<double>* row) {
                const std::size_t first = k * s.x.count;
                for (int j = 0; j < s.x.count; ++j)
                    row[j] = std::polar(s.weight[first + j], phase_per_height * s.height[first + j]);
            });
            s.weight = std::vector<double>();  // freed: `= {}` would keep the capacity
            s.height = std::vector<double>();
        }
        const std::lock_guard lock(mutex_);
        recent_.push_back({omega_i, layer, grid});
        if (recent_.size() > kKeptGrids * query_.wavelengths_um.size()) recent_.erase(recent_.begin());
        return grid;
    }

    static constexpr std::size_t kKeptGrids = 16;  // incidences
    struct Entry {
        Vec3 omega_i;
        std::size_t layer;
        std::shared_ptr<const IncidenceGrid> grid;
    };

    LobeQuery query_;
    double area_um2_;
    std::vector<ComplexIndex> indices_;
    mutable std::mutex mutex_;
    mutable std::vector<Entry> recent_;
};

}  // namespace

PointAnswers fft_point(const LobeQuery& query) {
    auto point = std::make_shared<const FftPoint>(query);
    PointAnswers answers;
    answers.eval = [point](Vec3 omega_i, Vec3 omega_o) { return point->eval(omega_i, omega_o); };
    answers.albedo = [query](Vec3 omega_i) {
        LobeQuery one = query;
        one.omega_i = omega_i;
        one.supersample = kAlbedoSupersample;
        const LobeImage image = fft_lobe(one);
        std::vector<double> albedo;
        for (std::size_t layer = 0; layer < image.layers(); ++layer) albedo.push_back(disk_sum(image, layer));
        return albedo;
    };
    return answers;
}

PointAnswersAt fft_point_field(const LobeQuery& query) {
    return [query](const Footprint& footprint) {
        LobeQuery one = query;
        one.footprint = footprint;
        return fft_point(one);
    };
}

}  // namespace glintscope
