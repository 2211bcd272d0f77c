#pragma once
// FFTW plans for batches of identical 1-D transforms run inside parallel_for.
//
// FFTW's planner is not thread-safe, so every plan is created and destroyed under one mutex.
// Executing a plan on other arrays (fftw_execute_dft & co.) is thread-safe as long as they have
// the alignment of the planning arrays; every buffer therefore comes from fftw_malloc. Plans are
// made with FFTW_ESTIMATE: FFTW_MEASURE would choose algorithms by timing, and results would
// change from run to run. One plan serves every row of a batch, so each row sees the same
// arithmetic whichever thread runs it.
#include <fftw3.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>

namespace glintscope {

std::mutex& fftw_planner_mutex();

struct FftwFree {
    void operator()(void* pointer) const { fftw_free(pointer); }
};

// An fftw_malloc'ed array of `count` elements of T (double, float, fftw_complex, fftwf_complex).
template <typename T>
using FftwBuffer = std::unique_ptr<T[], FftwFree>;

template <typename T>
FftwBuffer<T> make_fftw_buffer(std::size_t count) {
    auto* memory = static_cast<T*>(fftw_malloc(sizeof(T) * (count > 0 ? count : 1)));
    if (!memory) throw std::bad_alloc();
    return FftwBuffer<T>(memory);
}

// Scratch memory of the calling thread, aligned like fftw_malloc and kept for later calls with the
// same slot on the same thread, so a loop over many chunks does not map and fault fresh pages for
// every chunk. The contents are unspecified; a body must not use one slot for two live buffers.
void* thread_scratch_bytes(int slot, std::size_t bytes);
inline constexpr int kThreadScratchSlots = 4;

template <typename T>
T* thread_scratch(int slot, std::size_t count) {
    return static_cast<T*>(thread_scratch_bytes(slot, sizeof(T) * count));
}

// Owns a double or single precision plan; the constructor runs `make` under the planner mutex.
class FftwPlan {
public:
    explicit FftwPlan(const std::function<fftw_plan()>& make);
    ~FftwPlan();
    FftwPlan(const FftwPlan&) = delete;
    FftwPlan& operator=(const FftwPlan&) = delete;
    fftw_plan get() const { return plan_; }

private:
    fftw_plan plan_ = nullptr;
};

class FftwfPlan {
public:
    explicit FftwfPlan(const std::function<fftwf_plan()>& make);
    ~FftwfPlan();
    FftwfPlan(const FftwfPlan&) = delete;
    FftwfPlan& operator=(const FftwfPlan&) = delete;
    fftwf_plan get() const { return plan_; }

private:
    fftwf_plan plan_ = nullptr;
};

}  // namespace glintscope
