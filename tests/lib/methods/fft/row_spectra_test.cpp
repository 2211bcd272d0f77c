// Rows' transforms read from their oversampled spectra (row_spectra.hpp) against the direct sum.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "core/counter_rng.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/parallel.hpp"
#include "methods/fft/row_spectra.hpp"

namespace glintscope {
namespace {

// Rows read from real and imaginary parts stored row after row.
RowFill from(const std::vector<double>& re, const std::vector<double>& im, int length) {
    return [&re, &im, length](std::size_t k, std::complex<double>* row) {
        for (int j = 0; j < length; ++j) row[j] = {re[k * length + j], im[k * length + j]};
    };
}

// Rows like R* under a Gaussian window (σ an eighth of the row, as the fft grid's 4σ half-width)
// with random phases, so every frequency is reached; S_k(t) read from the spectra equals the
// direct sum Σ_j r_kj e^{−i2πtj} (in long double) within 3e-14 Σ_j |r_kj| (measured 0.6e-14 to
// 1.5e-14, growing with the length), at frequencies all over the period, beyond it and negative,
// for an odd and an even row length, and for 1093, where the smallest FFT-friendly size ≥ 2n
// would be odd (3⁷), misaligning all but the first row of a chunk for the plan.
TEST(RowSpectra, EqualTheDirectSumAtAnyFrequency) {
    const CounterRng rng(22, 1);
    for (int length : {151, 200, 1093}) {
        const int rows = 3;
        std::vector<double> re(static_cast<std::size_t>(length) * rows), im(re.size());
        for (std::size_t i = 0; i < re.size(); ++i) {
            const double x = (static_cast<double>(i % length) - 0.5 * (length - 1)) / (length / 8.0);
            const double phase = 2.0 * pi * rng.uniform(i);
            re[i] = std::exp(-0.5 * x * x) * std::cos(phase);
            im[i] = std::exp(-0.5 * x * x) * std::sin(phase);
        }
        const RowSpectra spectra = row_spectra(length, rows, from(re, im, length));
        for (int step = 0; step < 97; ++step) {
            const double t = -1.3 + 0.0277 * step;
            const SpectrumTaps taps = spectrum_taps(spectra, t);
            for (int k = 0; k < rows; ++k) {
                std::complex<long double> direct = 0.0L;
                double l1 = 0.0;
                for (int j = 0; j < length; ++j) {
                    const std::size_t at = static_cast<std::size_t>(k) * length + j;
                    const long double angle = -2.0L * pi * static_cast<long double>(t) * j;
                    direct += std::complex<long double>(re[at], im[at]) * std::complex<long double>(std::cos(angle), std::sin(angle));
                    l1 += std::hypot(re[at], im[at]);
                }
                std::complex<double> read = 0.0;
                for (int i = 0; i < taps.count; ++i) {
                    const std::size_t at = static_cast<std::size_t>(taps.bin[i]) * rows + k;
                    read += taps.weight[i] * std::complex<double>(spectra.re[at], spectra.im[at]);
                }
                read *= taps.phase;
                EXPECT_LT(std::abs(read - std::complex<double>(direct)), 3e-14 * l1)
                    << "length " << length << " row " << k << " t " << t;
            }
        }
    }
}

// Rows are transformed in chunks on the library's threads: the spectra are the same bits for one
// thread and for four.
TEST(RowSpectra, SameBitsForOneAndFourThreads) {
    const CounterRng rng(22, 2);
    const int length = 97, rows = 45;
    std::vector<double> re(static_cast<std::size_t>(length) * rows), im(re.size());
    for (std::size_t i = 0; i < re.size(); ++i) {
        re[i] = rng.uniform(2 * i, -1.0, 1.0);
        im[i] = rng.uniform(2 * i + 1, -1.0, 1.0);
    }
    const RowSpectra one = with_threads(1, [&] { return row_spectra(length, rows, from(re, im, length)); });
    const RowSpectra four = with_threads(4, [&] { return row_spectra(length, rows, from(re, im, length)); });
    EXPECT_EQ(one.re, four.re);
    EXPECT_EQ(one.im, four.im);
}

}  // namespace
}  // namespace glintscope
