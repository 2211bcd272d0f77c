#include "chirp_z.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>

#include "glintscope/core/geometry.hpp"

namespace glintscope {
namespace {

struct FftPlanPair {
    FftwPlan forward;
    FftwPlan backward;
};

// One in-place plan pair per size, made once and kept: plans are only read after creation, so
// every thread executes the same plan (fftw_execute_dft on its own fftw_malloc'ed buffers).
const FftPlanPair& plans_for_size(int size) {
    // The planner mutex is touched first so that it outlives the cache at program exit.
    static std::mutex& planner_mutex = fftw_planner_mutex();
    static std::mutex cache_mutex;
    static std::map<int, std::unique_ptr<FftPlanPair>> cache;
    (void)planner_mutex;
    std::lock_guard lock(cache_mutex);
    std::unique_ptr<FftPlanPair>& entry = cache[size];
    if (!entry) {
        auto buffer = make_fftw_buffer<fftw_complex>(static_cast<std::size_t>(size));
        const auto plan = [&](int sign) {
            return [&, sign] { return fftw_plan_dft_1d(size, buffer.get(), buffer.get(), sign, FFTW_ESTIMATE); };
        };
        entry.reset(new FftPlanPair{FftwPlan(plan(FFTW_FORWARD)), FftwPlan(plan(FFTW_BACKWARD))});
    }
    return *entry;
}

Complex* as_complex(fftw_complex* data) { return reinterpret_cast<Complex*>(data); }

}  // namespace

int smooth_fft_size(int n) {
    for (int candidate = std::max(n, 1);; ++candidate) {
        int rest = candidate;
        for (int prime : {2, 3, 5, 7})
            while (rest % prime == 0) rest /= prime;
        if (rest == 1) return candidate;
    }
}

int commensurate_fold(double sample_step, double frequency_step) {
    const double bins = 1.0 / std::fabs(sample_step * frequency_step);
    if (!(bins >= 1.0 && bins < 1e9)) return 0;
    const double nearest = std::round(bins);
    return std::fabs(bins - nearest) <= 1e-12 * bins ? static_cast<int>(nearest) : 0;
}

ChirpZ::ChirpZ(int input_count, int output_count, double sample_step, double first_frequency,
               double frequency_step)
    : input_count_(input_count), output_count_(output_count), frequency_step_(frequency_step),
      fft_size_(smooth_fft_size(input_count + output_count - 1)) {
    constexpr double two_pi = 2.0 * pi;
    const double shift = two_pi * sample_step * first_frequency;
    const int fold = commensurate_fold(sample_step, frequency_step);
    if (fold > 0 && fold < fft_size_ && smooth_fft_size(fold) == fold) {
        fold_size_ = fold;
        input_chirp_.resize(input_count_);
        for (int n = 0; n < input_count_; ++n) input_chirp_[n] = std::polar(1.0, -shift * double(n));
        // e^{−i2π r m h Δv} = e^{∓i2π r m/F}: FFTW's forward transform for Δv > 0, backward for Δv < 0.
        const FftPlanPair& plans = plans_for_size(fold_size_);
        forward_ = frequency_step > 0.0 ? plans.forward.get() : plans.backward.get();
        return;
    }
    const double theta = two_pi * sample_step * frequency_step;
    input_chirp_.resize(input_count_);
    for (int n = 0; n < input_count_; ++n) {
        const double nn = double(n);
        input_chirp_[n] = std::polar(1.0, -(shift * nn + 0.5 * theta * nn * nn));
    }
    output_chirp_.resize(output_count_);
    for (int m = 0; m < output_count_; ++m) output_chirp_[m] = std::polar(1.0, -0.5 * theta * double(m) * double(m));

    const FftPlanPair& plans = plans_for_size(fft_size_);
    forward_ = plans.forward.get();
    backward_ = plans.backward.get();

    // The chirp e^{iθq²/2} for lags q = m − n ∈ [−(L−1), M−1], laid out circularly (negative lags
    // at the end), transformed once; 1/P folds in the inverse FFT's normalisation.
    filter_spectrum_ = make_fftw_buffer<fftw_complex>(static_cast<std::size_t>(fft_size_));
    Complex* filter = as_complex(filter_spectrum_.get());
    std::fill(filter, filter + fft_size_, Complex(0.0, 0.0));
    const double scale = 1.0 / fft_size_;
    for (int q = -(input_count_ - 1); q < output_count_; ++q) {
        const double qq = double(q);
        filter[q >= 0 ? q : fft_size_ + q] = std::polar(scale, 0.5 * theta * qq * qq);
    }
    fftw_execute_dft(forward_, filter_spectrum_.get(), filter_spectrum_.get());
}

FftwBuffer<fftw_complex> ChirpZ::make_workspace() const {
    return make_fftw_buffer<fftw_complex>(static_cast<std::size_t>(fold_size_ ? fold_size_ : fft_size_));
}

void ChirpZ::transform(const Complex* input, Complex* output, fftw_complex* workspace) const {
    Complex* work = as_complex(workspace);
    if (fold_size_) {
        const int head = std::min(fold_size_, input_count_);  // the first block sets the bins
        for (int r = 0; r < head; ++r) work[r] = multiply(input[r], input_chirp_[r]);
        std::fill(work + head, work + fold_size_, Complex(0.0, 0.0));
        for (int first = fold_size_; first < input_count_; first += fold_size_) {
            const int count = std::min(fold_size_, input_count_ - first);
            for (int r = 0; r < count; ++r) work[r] += multiply(input[first + r], input_chirp_[first + r]);
        }
        fftw_execute_dft(forward_, workspace, workspace);
        for (int m = 0, r = 0; m < output_count_; ++m, r = r + 1 == fold_size_ ? 0 : r + 1) output[m] = work[r];
        return;
    }
    for (int n = 0; n < input_count_; ++n) work[n] = multiply(input[n], input_chirp_[n]);
    std::fill(work + input_count_, work + fft_size_, Complex(0.0, 0.0));
    fftw_execute_dft(forward_, workspace, workspace);
    const Complex* filter = as_complex(filter_spectrum_.get());
    for (int k = 0; k < fft_size_; ++k) work[k] = multiply(work[k], filter[k]);
    fftw_execute_dft(backward_, workspace, workspace);
    for (int m = 0; m < output_count_; ++m) output[m] = multiply(work[m], output_chirp_[m]);
}

}  // namespace glintscope
