#pragma once
// The inner loop of Gabor lobe images (gabor_lobe.cpp): for OHS and R-OHS every kernel's
// transform is separable on the regular image grid, c_k X_k(v_x) Y_k(v_y), so a tile of the
// field R̃*(v) is the complex matrix product U[r][c] = Σ_k A_k[r] B_k[c] over the kernels that
// reach it (A_k = c_k Y_k, B_k = X_k). Operands are single precision; each chunk of
// kChunkKernels kernels is summed in registers and then added to a double-precision tile.
namespace glintscope::gabor {

constexpr int kTileRows = 48;
constexpr int kTileCols = 64;
constexpr int kChunkKernels = 256;

// One kernel's operands on one tile, complex numbers as interleaved (Re, Im) floats:
// A block: A_k at the tile's kTileRows rows; B block: B_k at its kTileCols columns.
constexpr int kRowBlockFloats = 2 * kTileRows;
constexpr int kColBlockFloats = 2 * kTileCols;

// The product is computed in register blocks of kBlockRows rows × kBlockCols columns; blocks
// whose flag in `wanted` (row-major, kTileRows/kBlockRows × kTileCols/kBlockCols) is false are
// skipped (they lie outside the disk of directions).
constexpr int kBlockRows = 3;
constexpr int kBlockCols = 8;
constexpr int kBlocksPerTile = (kTileRows / kBlockRows) * (kTileCols / kBlockCols);

// u_re[r·kTileCols + c] += Re Σ_k A_k[r] B_k[c], likewise u_im, over `count` kernels.
void accumulate_tile(const float* const* a_blocks, const float* const* b_blocks, int count, const bool* wanted,
                     double* u_re, double* u_im);

}  // namespace glintscope::gabor
