#pragma once

// Clones of a hot function for the given targets, chosen once at load time by the CPU: the
// library stays portable and a modern CPU runs the wide code. The clones must stay out of line
// (GCC would otherwise inline the portable clone into its caller); Clang never inlines a
// multiversioned function and refuses noinline beside target_clones.
#if defined(__clang__)
#define GLINTSCOPE_CLONES_FOR(...) __attribute__((target_clones(__VA_ARGS__)))
#else
#define GLINTSCOPE_CLONES_FOR(...) [[gnu::noinline]] __attribute__((target_clones(__VA_ARGS__)))
#endif

// AVX2/FMA (x86-64-v3) and portable clones.
#define GLINTSCOPE_OUT_OF_LINE_CLONES GLINTSCOPE_CLONES_FOR("arch=x86-64-v3", "default")

// The same with an AVX-512 (x86-64-v4) clone too, of the same four-lane source: with its 32 vector
// registers the Gabor sums keep their exp and sincos polynomials' constants in registers instead
// of reloading them from the stack (BM_BsdfEval/gabor and the one-off point queries 2–7% faster
// on a Xeon, by the median of paired runs: docs/performance.md "AVX-512 for the Gabor sums").
#define GLINTSCOPE_OUT_OF_LINE_CLONES_V4 GLINTSCOPE_CLONES_FOR("arch=x86-64-v4", "arch=x86-64-v3", "default")

// A wider clone for CPUs with AVX-512 (x86-64-v4: F, VL, DQ, BW, CD), called where
// cpu_runs_avx512() says so. Kept apart from the clones above because its code is written for
// 512-bit vectors (the second-order Gabor sums' sixteen single-precision lanes,
// gabor_math::Single16, and the walk's eight-kernel writes), not compiled from the narrower source.
#define GLINTSCOPE_AVX512 [[gnu::noinline]] __attribute__((target("arch=x86-64-v4")))

namespace glintscope {
inline bool cpu_runs_avx512() {
    static const bool supported = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                                  __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
                                  __builtin_cpu_supports("avx512cd");
    return supported;
}
}  // namespace glintscope
