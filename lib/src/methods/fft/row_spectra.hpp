#pragma once
// Each row's discrete-time Fourier transform at ANY frequency from its spectrum sampled at least
// twice as finely as its length (a type-2 non-uniform FFT along the rows; Barnett, Magland &
// af Klinteberg 2019, "A parallel non-uniform fast Fourier transform library based on an
// 'exponential of semicircle' kernel"):
//   S_k(t) = Σ_{j<n} r_kj e^{−i2π t j}   (t in cycles per sample)
// as e^{−i2π t c} Σ_m K(t − m/L) G_k[m] over the bins m within w/2 of t·L (at most 17), with
// c = n/2 the centre, L = 2 × (the smallest FFT-friendly size ≥ n) the oversampled size,
// K(u) = e^{β(√(1 − (2Lu/w)²) − 1)} the kernel of width w = 16 bins (β = 2.30 w), and G_k the FFT
// of r_k(c + q)/(L K̂(q)), K̂ the kernel's Fourier transform (q the index about c). Against the
// direct sum the error is bounded by the spectral repeats K̂(q ± L)/K̂(q) and rounding:
// ≤ 1.6e-14 Σ_j |r_kj| measured for rows of 151–1093 samples (row_spectra_test.cpp), about the
// rounding of the direct sum itself.
#include <complex>
#include <cstddef>
#include <functional>
#include <vector>

namespace glintscope {

struct RowSpectra {
    int row_length = 0;  // n
    int rows = 0;
    int size = 0;              // L
    std::vector<double> re;    // G_k[m] at m·rows + k: one bin of every row contiguous
    std::vector<double> im;
};

// Writes the `row_length` samples r_kj of row k to row[j] (called from the library's threads,
// once per row).
using RowFill = std::function<void(std::size_t k, std::complex<double>* row)>;

// The spectra of `rows` rows of `row_length` samples (rows made and transformed in parallel;
// the same bits for any thread count).
RowSpectra row_spectra(int row_length, int rows, const RowFill& fill);

inline constexpr int kSpectrumTaps = 17;  // the bins within w/2 = 8 of t·L (at most 17)

// The bins and weights that give S_k(t) = phase · Σ_i weight[i] G_k[bin[i]] for every row k.
struct SpectrumTaps {
    int count = 0;
    int bin[kSpectrumTaps] = {};
    double weight[kSpectrumTaps] = {};
    std::complex<double> phase;  // e^{−i2π t c}
};
SpectrumTaps spectrum_taps(const RowSpectra& spectra, double t);

}  // namespace glintscope
