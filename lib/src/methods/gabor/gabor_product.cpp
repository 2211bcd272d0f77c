#include "gabor_product.hpp"

#include <algorithm>
#include <cstring>

namespace glintscope::gabor {
namespace {

// The SIMD helpers below are always inlined, so the vector calling convention that -Wpsabi
// warns about never applies.
#pragma GCC diagnostic ignored "-Wpsabi"

using Float8 = float __attribute__((vector_size(32)));  // 4 complex numbers, interleaved

constexpr int kBlockVectors = kBlockCols / 4;  // 4 complex numbers per vector

[[gnu::always_inline]] inline void load8(const float* values, Float8& v) { std::memcpy(&v, values, sizeof v); }

// Adds one register block to the double tile. by_re holds Re(a)·(Re b, Im b) and by_im holds
// Im(a)·(Re b, Im b) per complex lane, so a·b = (by_re.Re − by_im.Im, by_re.Im + by_im.Re).
[[gnu::always_inline]] inline void add_block(const Float8 (&by_re)[kBlockRows][kBlockVectors],
                                             const Float8 (&by_im)[kBlockRows][kBlockVectors], double* u_re,
                                             double* u_im) {
    for (int r = 0; r < kBlockRows; ++r)
        for (int v = 0; v < kBlockVectors; ++v) {
            const Float8 real = __builtin_shufflevector(by_re[r][v], by_re[r][v], 0, 2, 4, 6, 0, 2, 4, 6) -
                                __builtin_shufflevector(by_im[r][v], by_im[r][v], 1, 3, 5, 7, 1, 3, 5, 7);
            const Float8 imaginary = __builtin_shufflevector(by_re[r][v], by_re[r][v], 1, 3, 5, 7, 1, 3, 5, 7) +
                                     __builtin_shufflevector(by_im[r][v], by_im[r][v], 0, 2, 4, 6, 0, 2, 4, 6);
            double* row_re = u_re + r * kTileCols + 4 * v;
            double* row_im = u_im + r * kTileCols + 4 * v;
            for (int lane = 0; lane < 4; ++lane) {
                row_re[lane] += real[lane];
                row_im[lane] += imaginary[lane];
            }
        }
}

}  // namespace

// Each kernel costs 2 vector loads, 6 broadcasts and 12 fused multiply-adds per register block,
// into 12 independent accumulators (enough to hide the FMA latency).
__attribute__((target_clones("arch=x86-64-v3", "default")))
void accumulate_tile(const float* const* a_blocks, const float* const* b_blocks, int count, const bool* wanted,
                     double* u_re, double* u_im) {
    static_assert(kTileRows % kBlockRows == 0 && kTileCols % kBlockCols == 0);
    for (int start = 0; start < count; start += kChunkKernels) {
        const int end = std::min(count, start + kChunkKernels);
        for (int col = 0; col < kTileCols; col += kBlockCols)
            for (int row = 0; row < kTileRows; row += kBlockRows) {
                if (!wanted[(row / kBlockRows) * (kTileCols / kBlockCols) + col / kBlockCols]) continue;
                Float8 by_re[kBlockRows][kBlockVectors] = {};
                Float8 by_im[kBlockRows][kBlockVectors] = {};
                for (int k = start; k < end; ++k) {
                    Float8 b[kBlockVectors];
                    for (int v = 0; v < kBlockVectors; ++v) load8(b_blocks[k] + 2 * col + 8 * v, b[v]);
                    const float* a = a_blocks[k] + 2 * row;
                    for (int r = 0; r < kBlockRows; ++r)
                        for (int v = 0; v < kBlockVectors; ++v) {
                            by_re[r][v] += a[2 * r] * b[v];
                            by_im[r][v] += a[2 * r + 1] * b[v];
                        }
                }
                add_block(by_re, by_im, u_re + row * kTileCols + col, u_im + row * kTileCols + col);
            }
    }
}

}  // namespace glintscope::gabor
