// Rows' transforms at any frequency from their twice-oversampled spectra (row_spectra.hpp).
#include "row_spectra.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "glintscope/core/geometry.hpp"
#include "glintscope/core/parallel.hpp"
#include "numerics/chirp_z.hpp"
#include "numerics/fftw_plans.hpp"

namespace glintscope {
namespace {

constexpr int kWidth = kSpectrumTaps - 1;  // w, in bins of 1/L
constexpr double kBeta = 2.30 * kWidth;    // Barnett et al. 2019's choice at oversampling 2

// The kernel at z = 2Lu/w ∈ [−1, 1].
double kernel(double z) { return std::exp(kBeta * (std::sqrt(1.0 - z * z) - 1.0)); }

// 1/(L K̂(q)) for q = 0 … count − 1, K̂(q) = ∫ K(u) e^{i2πqu} du = (w/2L) ∫_{−1}^{1} K(z)
// cos(π q w z/L) dz by the trapezoidal rule over 128 nodes: K is smooth inside and falls to
// e^{−β} ≈ 1e-16 at z = ±1, so the rule converges fast (64, 128 and 512 nodes measured the same
// error of the spectra).
std::vector<double> deconvolution(int count, int size) {
    constexpr int kNodes = 128;
    const double dz = 2.0 / kNodes;
    std::vector<double> at_nodes(kNodes);
    for (int i = 1; i < kNodes; ++i) at_nodes[i] = kernel(-1.0 + i * dz);
    std::vector<double> inverse(count);
    for (int q = 0; q < count; ++q) {
        double sum = 0.0;
        for (int i = 1; i < kNodes; ++i) sum += at_nodes[i] * std::cos(pi * q * kWidth * (-1.0 + i * dz) / size);
        inverse[q] = 1.0 / (size * sum * dz * kWidth / (2.0 * size));
    }
    return inverse;
}

}  // namespace

RowSpectra row_spectra(int row_length, int rows, const RowFill& fill) {
    RowSpectra spectra;
    spectra.row_length = row_length;
    spectra.rows = rows;
    // Even, so that every row of a chunk (16·L bytes apart) keeps the planning buffer's alignment.
    spectra.size = 2 * smooth_fft_size(row_length);
    const int size = spectra.size, centre = row_length / 2;
    // For q = j − c; K̂ is even, so one value serves ±q.
    const std::vector<double> inverse_transform = deconvolution(std::max(centre, row_length - 1 - centre) + 1, size);
    spectra.re.resize(static_cast<std::size_t>(size) * rows);
    spectra.im.resize(spectra.re.size());
    // One plan for every row, each row made and transformed in its thread's scratch (aligned like
    // the planning buffer), so every row gets the same arithmetic on any thread. A chunk's rows
    // are transformed first and then written bin by bin, each bin's rows one contiguous run.
    constexpr std::size_t kChunk = 8;
    FftwBuffer<fftw_complex> planning = make_fftw_buffer<fftw_complex>(static_cast<std::size_t>(size));
    const FftwPlan plan([&] { return fftw_plan_dft_1d(size, planning.get(), planning.get(), FFTW_FORWARD, FFTW_ESTIMATE); });
    parallel_for(static_cast<std::size_t>(rows), kChunk, [&](std::size_t begin, std::size_t end) {
        fftw_complex* chunk = thread_scratch<fftw_complex>(0, kChunk * size);
        std::complex<double>* row = thread_scratch<std::complex<double>>(1, row_length);
        for (std::size_t k = begin; k < end; ++k) {
            fill(k, row);
            fftw_complex* a = chunk + (k - begin) * size;
            for (int m = 0; m < size; ++m) a[m][0] = a[m][1] = 0.0;
            for (int j = 0; j < row_length; ++j) {
                const int q = j - centre, bin = q >= 0 ? q : size + q;
                a[bin][0] = row[j].real() * inverse_transform[std::abs(q)];
                a[bin][1] = row[j].imag() * inverse_transform[std::abs(q)];
            }
            fftw_execute_dft(plan.get(), a, a);
        }
        for (int m = 0; m < size; ++m)
            for (std::size_t k = begin; k < end; ++k) {
                spectra.re[static_cast<std::size_t>(m) * rows + k] = chunk[(k - begin) * size + m][0];
                spectra.im[static_cast<std::size_t>(m) * rows + k] = chunk[(k - begin) * size + m][1];
            }
    });
    return spectra;
}

SpectrumTaps spectrum_taps(const RowSpectra& spectra, double t) {
    // S_k has period 1 in t: t − round(t) is exact and keeps t·L and t·c small, so that their
    // rounding moves the result no more than the direct sum's own.
    t -= std::nearbyint(t);
    SpectrumTaps taps;
    const double tl = t * spectra.size;
    const double half = 0.5 * kWidth;
    for (int m = static_cast<int>(std::ceil(tl - half)); m <= tl + half; ++m) {
        taps.bin[taps.count] = m < 0 ? m + spectra.size : m % spectra.size;
        taps.weight[taps.count] = kernel((tl - m) / half);
        ++taps.count;
    }
    // e^{−i2π t c} from t·c = p + e exactly (e by a fused multiply-add), p's whole cycles dropped.
    const double c = spectra.row_length / 2, p = t * c, e = std::fma(t, c, -p);
    taps.phase = std::polar(1.0, -2.0 * pi * ((p - std::nearbyint(p)) + e));
    return taps;
}

}  // namespace glintscope
