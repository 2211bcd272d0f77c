#pragma once
// The chirp-z transform (Rabiner, Schafer & Rader 1969) by Bluestein's algorithm: the sums
//   X_m = Σ_{n<L} x_n e^{−i2π n h (v0 + m Δv)},   m = 0 … M−1,
// at M frequencies on ANY regular grid, via one circular convolution of length P ≥ L + M − 1
// done with FFTW. An FFT only reaches the frequencies k/(P h); the chirp-z transform lets the
// FFT lobe evaluate R̃* exactly at each pixel's ψ̄/λ, with no bin lookup or interpolation.
//
// With nm = (n² + m² − (m − n)²)/2 the sum becomes a convolution with a chirp:
//   X_m = e^{−iθm²/2} Σ_n [x_n e^{−i2π h v0 n} e^{−iθn²/2}] e^{iθ(m−n)²/2},   θ = 2π h Δv.
//
// When the grids are commensurate, |h Δv| = 1/F for an integer F (a caller that may choose its
// step makes them so: fft_lobe.cpp), e^{−i2π n m h Δv} repeats every F inputs, and the sum is a
// plain DFT of length F of the modulated input folded onto F bins:
//   X_m = Σ_{r<F} [Σ_{n ≡ r (mod F)} x_n e^{−i2π h v0 n}] e^{∓i2π r m/F},   the sign that of Δv,
// exact as well, read at bin m mod F. The transform takes that path when F is a size FFTW does
// fast and smaller than the convolution's P: one FFT of F points instead of two of P ≥ L + M − 1.
#include <complex>
#include <vector>

#include "fftw_plans.hpp"

namespace glintscope {

using Complex = std::complex<double>;

// a·b without operator*'s C99 Annex G inf/NaN recovery, which keeps the hot loops from
// vectorising; every operand here is finite.
inline Complex multiply(Complex a, Complex b) {
    return {a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real()};
}

class ChirpZ {
public:
    // L inputs at spacing `sample_step`; M outputs at frequencies first_frequency + m·frequency_step
    // (cycles per unit length of sample_step). Plans come from a cache shared by all transforms.
    ChirpZ(int input_count, int output_count, double sample_step, double first_frequency, double frequency_step);

    int input_count() const { return input_count_; }
    int output_count() const { return output_count_; }
    double frequency_step() const { return frequency_step_; }
    // F when the transform folds (the grids are commensurate), else 0.
    int fold_size() const { return fold_size_; }
    // When it folds: the factor e^{−i2π h v0 n} of input n.
    Complex modulation(int n) const { return input_chirp_[n]; }

    // Scratch memory for transform(); each thread needs its own.
    FftwBuffer<fftw_complex> make_workspace() const;

    // output[m] = X_m for m < M from input[n], n < L. Thread-safe; the same input gives the same
    // bits on any thread.
    void transform(const Complex* input, Complex* output, fftw_complex* workspace) const;

private:
    int input_count_ = 0;
    int output_count_ = 0;
    double frequency_step_ = 0.0;
    int fft_size_ = 0;
    int fold_size_ = 0;
    std::vector<Complex> input_chirp_;          // e^{−i(2π h v0 n + θn²/2)}; folding: e^{−i2π h v0 n}
    std::vector<Complex> output_chirp_;         // e^{−iθm²/2}
    FftwBuffer<fftw_complex> filter_spectrum_;  // FFT of e^{iθq²/2} (q = −(L−1) … M−1), divided by P
    fftw_plan forward_ = nullptr;
    fftw_plan backward_ = nullptr;
};

// The smallest n' ≥ n whose prime factors are all 2, 3, 5 or 7 (sizes FFTW transforms fastest).
int smooth_fft_size(int n);

// F if |sample_step · frequency_step| = 1/F for an integer F ≥ 1 (to 1e-12 relative), else 0.
int commensurate_fold(double sample_step, double frequency_step);

}  // namespace glintscope
