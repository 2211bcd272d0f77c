#include "fftw_plans.hpp"

#include <array>
#include <new>

#include "glintscope/core/error.hpp"

namespace glintscope {

std::mutex& fftw_planner_mutex() {
    static std::mutex mutex;
    return mutex;
}

void* thread_scratch_bytes(int slot, std::size_t bytes) {
    struct Scratch {
        FftwBuffer<char> memory;
        std::size_t bytes = 0;
    };
    thread_local std::array<Scratch, kThreadScratchSlots> scratch;
    if (slot < 0 || slot >= kThreadScratchSlots) throw Error("internal: thread scratch slot out of range");
    Scratch& entry = scratch[slot];
    if (entry.bytes < bytes) {
        entry.memory.reset();
        entry.memory = make_fftw_buffer<char>(bytes);
        entry.bytes = bytes;
    }
    return entry.memory.get();
}

FftwPlan::FftwPlan(const std::function<fftw_plan()>& make) {
    std::lock_guard lock(fftw_planner_mutex());
    plan_ = make();
    if (!plan_) throw std::bad_alloc();
}

FftwPlan::~FftwPlan() {
    std::lock_guard lock(fftw_planner_mutex());
    fftw_destroy_plan(plan_);
}

FftwfPlan::FftwfPlan(const std::function<fftwf_plan()>& make) {
    std::lock_guard lock(fftw_planner_mutex());
    plan_ = make();
    if (!plan_) throw std::bad_alloc();
}

FftwfPlan::~FftwfPlan() {
    std::lock_guard lock(fftw_planner_mutex());
    fftwf_destroy_plan(plan_);
}

}  // namespace glintscope
