// Inpainting of missing heightfield points (profilometer drop-outs). Dong 2015 §4.1 treats such
// points as missing data and found hole filling unnecessary for its predictions; every method here
// samples one interpolant over the whole field, so the holes must hold heights.
//
// The filled heights minimise a smoothness energy, a sum of squared finite differences, with
// the valid heights held fixed:
//   harmonic    E = Σ (u_x)² + (u_y)²             (membrane; Euler–Lagrange ΔH = 0 in a hole)
//   biharmonic  E = Σ (u_xx)² + 2 (u_xy)² + (u_yy)²  (thin plate; Δ²H = 0 in a hole)
// with u_x = u[r][c+1] − u[r][c], u_xx = u[r][c−1] − 2 u[r][c] + u[r][c+1] and u_xy over each 2×2
// cell. Inside the field the thin-plate equations are the 13-point Δ² stencil, which carries
// every cubic through a hole exactly. With Tiling::none a difference is counted only where its
// points all lie in the field, which gives each energy its natural (free) boundary condition
// at the border: a hole touching the border continues the surface rather than pinning it to
// anything outside, and the thin plate continues a plane there exactly. Restricted to the
// unknowns both energies are positive-definite quadratics (any fixed point removes the
// constants and planes they do not see), solved by conjugate gradients (CG).
//
// Holes that do not interact (no difference touches both) are independent problems: small ones
// are solved directly and in parallel; on a large one CG alone would need O(diameter)
// (harmonic) or O(diameter²) (biharmonic) iterations, so a multigrid V-cycle preconditions it
// (see "Multigrid" below).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/prepare/prepare.hpp"

namespace glintscope {
namespace {

// Vector operations below this length run on one thread: starting threads would cost more.
constexpr std::size_t kChunk = 32768;
// CG stops when |b − A x| ≤ kTolerance·|b|: far below the float rounding of the heights.
constexpr double kTolerance = 1e-9;
constexpr int kMaxIterations = 20000;
// Systems up to this size are solved directly (dense L D Lᵀ); larger holes by CG with a
// multigrid preconditioner.
constexpr std::size_t kDirectSolveLimit = 256;
constexpr std::int32_t kNone = -1;

// parallel_for with chunks of kChunk; a single chunk runs inline, sparing small holes the
// start-up of threads. The chunks, and so every result, do not depend on the thread count.
template <typename Body>
void for_chunks(std::size_t count, Body&& body) {
    if (count <= kChunk) {
        if (count > 0) body(std::size_t{0}, count);
        return;
    }
    parallel_for(count, kChunk, body);
}

// Heights with NaN where a point is unknown.
struct Grid {
    int rows = 0;
    int cols = 0;
    const float* values = nullptr;

    std::size_t size() const { return static_cast<std::size_t>(rows) * cols; }
    bool unknown(std::size_t p) const { return std::isnan(values[p]); }
};

// ---- Holes ---------------------------------------------------------------------------------

// Groups the unknowns into independent problems. Unknowns interact when a difference of the
// energy holds both: grid neighbours for the membrane, points up to two steps apart
// (|Δr| + |Δc| ≤ 2) for the thin plate. Each
// group is listed in row-major order; groups are ordered by their first point. `label` (one
// entry per grid point) is left holding kNone at every valid point.
std::vector<std::vector<std::size_t>> find_holes(const Grid& grid, FillMethod method, Tiling tiling,
                                                 std::vector<std::int32_t>& label) {
    static constexpr std::array<std::array<int, 2>, 12> kOffsets{
        {{-1, 0}, {1, 0}, {0, -1}, {0, 1}, {-2, 0}, {2, 0}, {0, -2}, {0, 2}, {-1, -1}, {-1, 1}, {1, -1}, {1, 1}}};
    const int reach = method == FillMethod::harmonic ? 4 : 12;
    label.assign(grid.size(), kNone);
    std::vector<std::vector<std::size_t>> holes;
    for (std::size_t start = 0; start < grid.size(); ++start) {
        if (!grid.unknown(start) || label[start] != kNone) continue;
        const auto id = static_cast<std::int32_t>(holes.size());
        std::vector<std::size_t> hole{start};
        label[start] = id;
        for (std::size_t next = 0; next < hole.size(); ++next) {
            const int r = static_cast<int>(hole[next] / grid.cols);
            const int c = static_cast<int>(hole[next] % grid.cols);
            for (int k = 0; k < reach; ++k) {
                int rr = r + kOffsets[k][0];
                int cc = c + kOffsets[k][1];
                if (tiling == Tiling::periodic) {
                    rr = ((rr % grid.rows) + grid.rows) % grid.rows;
                    cc = ((cc % grid.cols) + grid.cols) % grid.cols;
                } else if (rr < 0 || rr >= grid.rows || cc < 0 || cc >= grid.cols) {
                    continue;
                }
                const std::size_t q = static_cast<std::size_t>(rr) * grid.cols + cc;
                if (!grid.unknown(q) || label[q] != kNone) continue;
                label[q] = id;
                hole.push_back(q);
            }
        }
        std::sort(hole.begin(), hole.end());
        holes.push_back(std::move(hole));
    }
    return holes;
}

// ---- Sparse matrices ----------------------------------------------------------------------

// Compressed rows; rows and columns are the unknowns of one level.
struct SparseMatrix {
    std::vector<std::size_t> row_start{0};
    std::vector<std::int32_t> column;
    std::vector<double> value;
    std::vector<double> diagonal;  // a_ii, for Jacobi
    std::vector<double> l1_norm;   // Σ_j |a_ij|, for the ℓ1-Jacobi smoother

    std::size_t size() const { return row_start.size() - 1; }
};

// Accumulates one row's entries, summing repeated columns; slot_ finds a column's entry
// without a search (the Galerkin rows sum hundreds of products into a few dozen entries).
class RowBuilder {
public:
    explicit RowBuilder(std::size_t columns) : slot_(columns, kNone) {}
    void add(std::int32_t column, double value) {
        std::int32_t& slot = slot_[static_cast<std::size_t>(column)];
        if (slot == kNone) {
            slot = static_cast<std::int32_t>(entries_.size());
            entries_.emplace_back(column, value);
        } else {
            entries_[static_cast<std::size_t>(slot)].second += value;
        }
    }
    const std::vector<std::pair<std::int32_t, double>>& entries() const { return entries_; }
    void clear() {
        for (const auto& entry : entries_) slot_[static_cast<std::size_t>(entry.first)] = kNone;
        entries_.clear();
    }

private:
    std::vector<std::int32_t> slot_;
    std::vector<std::pair<std::int32_t, double>> entries_;
};

// Builds a rows×columns matrix; fill_row(i, builder) adds row i's entries. Rows are built in
// fixed chunks in parallel and joined in order.
template <typename FillRow>
SparseMatrix build_matrix(std::size_t rows, std::size_t columns, FillRow&& fill_row) {
    struct Chunk {
        std::vector<std::size_t> length;
        std::vector<std::int32_t> column;
        std::vector<double> value;
    };
    std::vector<Chunk> chunks((rows + kChunk - 1) / kChunk);
    SparseMatrix matrix;
    matrix.diagonal.resize(rows);
    matrix.l1_norm.resize(rows);
    for_chunks(rows, [&](std::size_t begin, std::size_t end) {
        Chunk& chunk = chunks[begin / kChunk];
        RowBuilder row(columns);
        for (std::size_t i = begin; i < end; ++i) {
            row.clear();
            fill_row(i, row);
            double l1 = 0.0;
            for (const auto& [j, a] : row.entries()) {
                if (static_cast<std::size_t>(j) == i) matrix.diagonal[i] = a;
                l1 += std::fabs(a);
                chunk.column.push_back(j);
                chunk.value.push_back(a);
            }
            matrix.l1_norm[i] = l1;
            chunk.length.push_back(row.entries().size());
        }
    });
    matrix.row_start.reserve(rows + 1);
    for (Chunk& chunk : chunks) {
        for (std::size_t length : chunk.length) matrix.row_start.push_back(matrix.row_start.back() + length);
        matrix.column.insert(matrix.column.end(), chunk.column.begin(), chunk.column.end());
        matrix.value.insert(matrix.value.end(), chunk.value.begin(), chunk.value.end());
        chunk = {};
    }
    return matrix;
}

void multiply(const SparseMatrix& a, const std::vector<double>& x, std::vector<double>& y) {
    for_chunks(a.size(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            double sum = 0.0;
            for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e)
                sum += a.value[e] * x[static_cast<std::size_t>(a.column[e])];
            y[i] = sum;
        }
    });
}

// Σ a_k b_k, summed per fixed chunk and then in chunk order: identical for any thread count.
double dot(const std::vector<double>& a, const std::vector<double>& b) {
    std::vector<double> partial((a.size() + kChunk - 1) / kChunk, 0.0);
    for_chunks(a.size(), [&](std::size_t begin, std::size_t end) {
        double sum = 0.0;
        for (std::size_t k = begin; k < end; ++k) sum += a[k] * b[k];
        partial[begin / kChunk] = sum;
    });
    double total = 0.0;
    for (double sum : partial) total += sum;
    return total;
}

// ---- The linear system of one hole ---------------------------------------------------------

struct HoleSystem {
    SparseMatrix matrix;      // A, on the hole's unknowns
    std::vector<double> rhs;  // b: the pull of the valid heights
};

// One finite difference d(u) = Σ_k α_k u(point_k) of the energy E = Σ weight·d².
struct Difference {
    int count = 0;
    std::array<std::size_t, 4> point{};
    std::array<double, 4> alpha{};
    double weight = 1.0;
};

// The differences of the energy that involve grid point p, each once.
class DifferencesAround {
public:
    DifferencesAround(const Grid& grid, FillMethod method, Tiling tiling) : grid_(grid), tiling_(tiling) {
        if (method == FillMethod::harmonic) {
            // u_x on the edge from (r, c) to (r, c + 1), u_y likewise: anchored at their first point.
            stencils_.push_back({1.0, {{{0, 0}, {0, 1}}}, {1.0, -1.0}, 2, {{{0, 0}, {0, -1}}}, 2});
            stencils_.push_back({1.0, {{{0, 0}, {1, 0}}}, {1.0, -1.0}, 2, {{{0, 0}, {-1, 0}}}, 2});
        } else {
            // u_xx and u_yy centred on the anchor, u_xy on the cell whose top-left is the anchor.
            stencils_.push_back(
                {1.0, {{{0, -1}, {0, 0}, {0, 1}}}, {1.0, -2.0, 1.0}, 3, {{{0, 1}, {0, 0}, {0, -1}}}, 3});
            stencils_.push_back(
                {1.0, {{{-1, 0}, {0, 0}, {1, 0}}}, {1.0, -2.0, 1.0}, 3, {{{1, 0}, {0, 0}, {-1, 0}}}, 3});
            stencils_.push_back({2.0, {{{0, 0}, {0, 1}, {1, 0}, {1, 1}}}, {1.0, -1.0, -1.0, 1.0}, 4,
                                 {{{0, 0}, {0, -1}, {-1, 0}, {-1, -1}}}, 4});
        }
    }

    template <typename Visit>
    void for_each(std::size_t p, Visit&& visit) const {
        const int r = static_cast<int>(p / grid_.cols);
        const int c = static_cast<int>(p % grid_.cols);
        for (const Stencil& stencil : stencils_) {
            // Anchors at which the stencil covers p; under periodic tiling two may coincide.
            std::array<std::size_t, 4> seen{};
            int seen_count = 0;
            for (int a = 0; a < stencil.anchor_count; ++a) {
                const auto anchor = locate(r + stencil.anchors[a][0], c + stencil.anchors[a][1]);
                if (!anchor) continue;
                if (std::find(seen.begin(), seen.begin() + seen_count, *anchor) != seen.begin() + seen_count) continue;
                seen[seen_count++] = *anchor;
                Difference difference;
                difference.weight = stencil.weight;
                const int ar = static_cast<int>(*anchor / grid_.cols);
                const int ac = static_cast<int>(*anchor % grid_.cols);
                bool inside = true;
                for (int k = 0; k < stencil.count && inside; ++k) {
                    const auto point = locate(ar + stencil.offsets[k][0], ac + stencil.offsets[k][1]);
                    inside = point.has_value();
                    if (inside) difference.point[k] = *point;
                    difference.alpha[k] = stencil.alpha[k];
                }
                difference.count = stencil.count;
                if (inside) visit(difference);
            }
        }
    }

private:
    struct Stencil {
        double weight;
        std::array<std::array<int, 2>, 4> offsets;  // (Δrow, Δcol) from the anchor
        std::array<double, 4> alpha;
        int count;
        std::array<std::array<int, 2>, 4> anchors;  // anchors whose stencil covers (0, 0)
        int anchor_count;
    };

    std::optional<std::size_t> locate(int r, int c) const {
        if (tiling_ == Tiling::periodic) {
            r = ((r % grid_.rows) + grid_.rows) % grid_.rows;
            c = ((c % grid_.cols) + grid_.cols) % grid_.cols;
        } else if (r < 0 || r >= grid_.rows || c < 0 || c >= grid_.cols) {
            return std::nullopt;
        }
        return static_cast<std::size_t>(r) * grid_.cols + c;
    }

    const Grid& grid_;
    Tiling tiling_;
    std::vector<Stencil> stencils_;
};

// Setting ∂E/∂u_p = Σ_d 2 w α_p d(u) to zero for every unknown p gives A x = b with
//   A_pq = Σ_d w α_p α_q over unknown q,   b_p = −Σ_d w α_p α_k u_k over valid k.
// `hole` must be one whole hole (row-major); `index` maps grid points to the hole's unknowns.
// A hole's differences touch only points within two steps of it, none of which is another
// hole's unknown, so holes can be set up concurrently with one shared index map.
HoleSystem build_hole_system(const Grid& grid, const std::vector<std::size_t>& hole, FillMethod method,
                             Tiling tiling, std::vector<std::int32_t>& index) {
    for (std::size_t k = 0; k < hole.size(); ++k) index[hole[k]] = static_cast<std::int32_t>(k);
    const DifferencesAround differences(grid, method, tiling);
    HoleSystem system;
    system.rhs.assign(hole.size(), 0.0);
    system.matrix = build_matrix(hole.size(), hole.size(), [&](std::size_t i, RowBuilder& row) {
        const std::size_t p = hole[i];
        double rhs = 0.0;
        differences.for_each(p, [&](const Difference& d) {
            double alpha_p = 0.0;  // a wrapped stencil may visit p twice
            for (int k = 0; k < d.count; ++k)
                if (d.point[k] == p) alpha_p += d.alpha[k];
            if (alpha_p == 0.0) return;
            for (int k = 0; k < d.count; ++k) {
                const double coupling = d.weight * alpha_p * d.alpha[k];
                if (grid.unknown(d.point[k]))
                    row.add(index[d.point[k]], coupling);
                else
                    rhs -= coupling * grid.values[d.point[k]];
            }
        });
        system.rhs[i] = rhs;
    });
    return system;
}

// ---- Conjugate gradients -------------------------------------------------------------------

// z = M⁻¹ r.
using Preconditioner = std::function<void(const std::vector<double>& r, std::vector<double>& z)>;

struct SolveResult {
    int iterations = 0;
    double relative_residual = 0.0;
};

// Preconditioned CG for A x = b from the initial guess in x, until |b − A x| ≤ tolerance·|b|.
SolveResult conjugate_gradients(const SparseMatrix& a, const std::vector<double>& b, std::vector<double>& x,
                                double tolerance, const Preconditioner& precondition) {
    const std::size_t n = a.size();
    const double b_norm = std::sqrt(dot(b, b));
    if (b_norm == 0.0) {
        std::fill(x.begin(), x.end(), 0.0);
        return {};
    }
    std::vector<double> r(n), z(n), p(n), q(n);
    multiply(a, x, q);
    for_chunks(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) r[k] = b[k] - q[k];
    });
    double r_norm = std::sqrt(dot(r, r));
    precondition(r, z);
    p = z;
    double rz = dot(r, z);
    int iteration = 0;
    while (iteration < kMaxIterations && r_norm > tolerance * b_norm) {
        ++iteration;
        multiply(a, p, q);
        const double alpha = rz / dot(p, q);
        for_chunks(n, [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) {
                x[k] += alpha * p[k];
                r[k] -= alpha * q[k];
            }
        });
        r_norm = std::sqrt(dot(r, r));
        if (r_norm <= tolerance * b_norm) break;
        precondition(r, z);
        const double rz_next = dot(r, z);
        const double beta = rz_next / rz;
        rz = rz_next;
        for_chunks(n, [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) p[k] = z[k] + beta * p[k];
        });
    }
    return {iteration, r_norm / b_norm};
}

Preconditioner jacobi(const SparseMatrix& a) {
    return [&a](const std::vector<double>& r, std::vector<double>& z) {
        for_chunks(a.size(), [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) z[k] = r[k] / a.diagonal[k];
        });
    };
}

// ---- Direct solution of small systems ------------------------------------------------------

// A = L D Lᵀ of a small symmetric positive (semi)definite matrix, in band storage: with the
// unknowns in row-major order a hole's matrix is banded (about one hole width), and the
// factors fill in only inside the band. A pivot that vanishes — a Galerkin coarse matrix is
// singular where a coarse point draws on too few fine points — is skipped, which still solves
// the consistent systems the multigrid cycle hands it.
class DenseSolver {
public:
    explicit DenseSolver(const SparseMatrix& a) : n_(a.size()) {
        for (std::size_t i = 0; i < n_; ++i)
            for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e)
                band_ = std::max(band_, i - std::min(i, static_cast<std::size_t>(a.column[e])));
        factor_.assign(n_ * (band_ + 1), 0.0);
        for (std::size_t i = 0; i < n_; ++i)
            for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e) {
                const auto j = static_cast<std::size_t>(a.column[e]);
                if (j <= i) at(i, j) = a.value[e];
            }
        for (std::size_t j = 0; j < n_; ++j) {
            const std::size_t first = j - std::min(j, band_);
            double d = at(j, j);
            for (std::size_t k = first; k < j; ++k) d -= at(j, k) * at(j, k) * at(k, k);
            const bool vanishes = !(d > 1e-12 * a.diagonal[j]);
            at(j, j) = vanishes ? 0.0 : d;
            for (std::size_t i = j + 1; i < std::min(n_, j + band_ + 1); ++i) {
                if (vanishes) {
                    at(i, j) = 0.0;
                    continue;
                }
                double sum = at(i, j);
                for (std::size_t k = i - std::min(i, band_); k < j; ++k) sum -= at(i, k) * at(j, k) * at(k, k);
                at(i, j) = sum / d;
            }
        }
    }

    void solve(const std::vector<double>& b, std::vector<double>& x) const {
        for (std::size_t i = 0; i < n_; ++i) {
            double sum = b[i];
            for (std::size_t k = i - std::min(i, band_); k < i; ++k) sum -= at(i, k) * x[k];
            x[i] = sum;
        }
        for (std::size_t i = 0; i < n_; ++i) x[i] = at(i, i) > 0.0 ? x[i] / at(i, i) : 0.0;
        for (std::size_t i = n_; i-- > 0;) {
            double sum = x[i];
            for (std::size_t k = i + 1; k < std::min(n_, i + band_ + 1); ++k) sum -= at(k, i) * x[k];
            x[i] = sum;
        }
    }

private:
    // Entry (i, j), i − band ≤ j ≤ i, of the lower triangle.
    double& at(std::size_t i, std::size_t j) { return factor_[i * (band_ + 1) + (j + band_ - i)]; }
    double at(std::size_t i, std::size_t j) const { return factor_[i * (band_ + 1) + (j + band_ - i)]; }

    std::size_t n_ = 0;
    std::size_t band_ = 0;
    std::vector<double> factor_;  // row i holds L_ij for j in [i − band, i), D_i at j = i
};

// ---- Multigrid -----------------------------------------------------------------------------
//
// A V-cycle preconditions CG on large holes. Each coarser level has half the resolution: a
// fine unknown at row r sits at coarse row (r + 0.5)/2 − 0.5, and corrections are interpolated
// bilinearly from the coarse points around it (P, clamped at the grid's edges); the coarse
// unknowns are every coarse point some fine unknown draws on. The coarse operator is the
// Galerkin product A_2h = Pᵀ A_h P and residuals are restricted by Pᵀ, so the coarse problem
// is the fine one's best approximation however ragged the hole's rim is. The smoother is
// ℓ1-Jacobi, x += ω (f − A x) / Σ_j |a_ij|, which converges for any ω < 2; ω = 1.6 gives the
// classic damping 4/5 on the interior Laplacian. Equal smoothing before and after the coarse
// correction keeps the V-cycle symmetric positive definite, as CG requires.

constexpr std::size_t kCoarsestUnknowns = 128;
constexpr int kSmoothingSweeps = 2;
constexpr double kSmootherDamping = 1.6;
// Coarsening stops when a level would not shrink below this fraction of the finer one.
constexpr double kMinimumCoarsening = 0.75;

struct Level {
    int rows = 0;                         // this level's grid
    int cols = 0;
    std::vector<std::size_t> position;    // grid point of each unknown, row-major
    SparseMatrix matrix;
    // P from the next coarser level: up to four (coarse unknown, weight) pairs per unknown here.
    std::vector<std::array<std::int32_t, 4>> coarse_index;
    std::vector<std::array<double, 4>> coarse_weight;
    // Pᵀ as rows per coarse unknown: (unknown here, weight).
    std::vector<std::size_t> restrict_start;
    std::vector<std::int32_t> restrict_index;
    std::vector<double> restrict_weight;
    std::vector<double> residual, coarse_rhs, coarse_solution;  // V-cycle scratch
    std::optional<DenseSolver> direct;                          // the coarsest level, when small
};

// Sets up the prolongation of `fine` from a new coarser level and returns that level's
// geometry (its matrix still empty).
Level coarsen(Level& fine) {
    Level coarse;
    coarse.rows = (fine.rows + 1) / 2;
    coarse.cols = (fine.cols + 1) / 2;
    const std::size_t n = fine.position.size();
    std::vector<std::array<std::size_t, 4>> corner(n);
    fine.coarse_weight.resize(n);
    for_chunks(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::size_t p = fine.position[k];
            const double v = std::clamp(0.5 * static_cast<double>(p / fine.cols) - 0.25, 0.0, coarse.rows - 1.0);
            const double u = std::clamp(0.5 * static_cast<double>(p % fine.cols) - 0.25, 0.0, coarse.cols - 1.0);
            const auto r0 = static_cast<std::size_t>(v);
            const auto c0 = static_cast<std::size_t>(u);
            const std::size_t r1 = std::min<std::size_t>(r0 + 1, coarse.rows - 1);
            const std::size_t c1 = std::min<std::size_t>(c0 + 1, coarse.cols - 1);
            const double fv = v - static_cast<double>(r0);
            const double fu = u - static_cast<double>(c0);
            const std::size_t cols = coarse.cols;
            corner[k] = {r0 * cols + c0, r0 * cols + c1, r1 * cols + c0, r1 * cols + c1};
            fine.coarse_weight[k] = {(1 - fv) * (1 - fu), (1 - fv) * fu, fv * (1 - fu), fv * fu};
        }
    });
    for (std::size_t k = 0; k < n; ++k)
        for (int m = 0; m < 4; ++m)
            if (fine.coarse_weight[k][m] > 0.0) coarse.position.push_back(corner[k][m]);
    std::sort(coarse.position.begin(), coarse.position.end());
    coarse.position.erase(std::unique(coarse.position.begin(), coarse.position.end()), coarse.position.end());
    fine.coarse_index.resize(n);
    for_chunks(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k)
            for (int m = 0; m < 4; ++m) {
                fine.coarse_index[k][m] = kNone;
                if (fine.coarse_weight[k][m] <= 0.0) continue;
                const auto found = std::lower_bound(coarse.position.begin(), coarse.position.end(), corner[k][m]);
                fine.coarse_index[k][m] = static_cast<std::int32_t>(found - coarse.position.begin());
            }
    });
    // Pᵀ by counting sort on the coarse index, fine unknowns in increasing order within a row.
    fine.restrict_start.assign(coarse.position.size() + 1, 0);
    for (const auto& indices : fine.coarse_index)
        for (std::int32_t j : indices)
            if (j != kNone) ++fine.restrict_start[static_cast<std::size_t>(j) + 1];
    for (std::size_t j = 0; j < coarse.position.size(); ++j) fine.restrict_start[j + 1] += fine.restrict_start[j];
    fine.restrict_index.resize(fine.restrict_start.back());
    fine.restrict_weight.resize(fine.restrict_start.back());
    std::vector<std::size_t> fill(fine.restrict_start.begin(), fine.restrict_start.end() - 1);
    for (std::size_t k = 0; k < n; ++k)
        for (int m = 0; m < 4; ++m) {
            const std::int32_t j = fine.coarse_index[k][m];
            if (j == kNone) continue;
            const std::size_t slot = fill[static_cast<std::size_t>(j)]++;
            fine.restrict_index[slot] = static_cast<std::int32_t>(k);
            fine.restrict_weight[slot] = fine.coarse_weight[k][m];
        }
    return coarse;
}

// A_2h = Pᵀ (A_h P), with A_h P formed first: its rows have at most 16 entries, where A_h's
// rows times P's would add some 50 products per fine row into each coarse row.
SparseMatrix galerkin_product(const Level& fine, std::size_t coarse_unknowns) {
    const SparseMatrix& a = fine.matrix;
    const SparseMatrix ap = build_matrix(a.size(), coarse_unknowns, [&](std::size_t i, RowBuilder& builder) {
        for (std::size_t e = a.row_start[i]; e < a.row_start[i + 1]; ++e) {
            const auto j = static_cast<std::size_t>(a.column[e]);
            for (int m = 0; m < 4; ++m)
                if (fine.coarse_index[j][m] != kNone)
                    builder.add(fine.coarse_index[j][m], a.value[e] * fine.coarse_weight[j][m]);
        }
    });
    return build_matrix(coarse_unknowns, coarse_unknowns, [&](std::size_t row, RowBuilder& builder) {
        for (std::size_t e = fine.restrict_start[row]; e < fine.restrict_start[row + 1]; ++e) {
            const auto i = static_cast<std::size_t>(fine.restrict_index[e]);
            for (std::size_t f = ap.row_start[i]; f < ap.row_start[i + 1]; ++f)
                builder.add(ap.column[f], fine.restrict_weight[e] * ap.value[f]);
        }
    });
}

std::vector<Level> build_hierarchy(Level finest) {
    std::vector<Level> levels;
    levels.push_back(std::move(finest));
    while (levels.back().position.size() > kCoarsestUnknowns) {
        Level coarse = coarsen(levels.back());
        if (static_cast<double>(coarse.position.size()) >
            kMinimumCoarsening * static_cast<double>(levels.back().position.size())) {
            levels.back().coarse_index.clear();
            levels.back().coarse_weight.clear();
            break;
        }
        coarse.matrix = galerkin_product(levels.back(), coarse.position.size());
        levels.push_back(std::move(coarse));
    }
    if (levels.back().position.size() <= kDirectSolveLimit) levels.back().direct.emplace(levels.back().matrix);
    for (std::size_t k = 0; k < levels.size(); ++k) {
        levels[k].residual.resize(levels[k].position.size());
        if (k + 1 < levels.size()) {
            levels[k].coarse_rhs.resize(levels[k + 1].position.size());
            levels[k].coarse_solution.resize(levels[k + 1].position.size());
        }
    }
    return levels;
}

// x ≈ A⁻¹ f on level k: one V-cycle from x = 0 (CG to round-off on the coarsest level).
void v_cycle(std::vector<Level>& levels, std::size_t k, const std::vector<double>& f, std::vector<double>& x) {
    Level& level = levels[k];
    const SparseMatrix& a = level.matrix;
    const std::size_t n = a.size();
    if (k + 1 == levels.size()) {
        if (level.direct) {
            level.direct->solve(f, x);
        } else {
            std::fill(x.begin(), x.end(), 0.0);
            conjugate_gradients(a, f, x, 1e-12, jacobi(a));
        }
        return;
    }
    const auto smooth = [&] {
        multiply(a, x, level.residual);
        for_chunks(n, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i)
                x[i] += kSmootherDamping * (f[i] - level.residual[i]) / a.l1_norm[i];
        });
    };
    std::fill(x.begin(), x.end(), 0.0);
    for (int sweep = 0; sweep < kSmoothingSweeps; ++sweep) smooth();

    multiply(a, x, level.residual);
    for_chunks(level.coarse_rhs.size(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t j = begin; j < end; ++j) {
            double sum = 0.0;
            for (std::size_t e = level.restrict_start[j]; e < level.restrict_start[j + 1]; ++e) {
                const auto i = static_cast<std::size_t>(level.restrict_index[e]);
                sum += level.restrict_weight[e] * (f[i] - level.residual[i]);
            }
            level.coarse_rhs[j] = sum;
        }
    });
    v_cycle(levels, k + 1, level.coarse_rhs, level.coarse_solution);
    for_chunks(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            for (int m = 0; m < 4; ++m)
                if (level.coarse_index[i][m] != kNone)
                    x[i] += level.coarse_weight[i][m] *
                            level.coarse_solution[static_cast<std::size_t>(level.coarse_index[i][m])];
    });
    for (int sweep = 0; sweep < kSmoothingSweeps; ++sweep) smooth();
}

// ---- One hole ------------------------------------------------------------------------------

// |b − A x| / |b|.
double relative_residual(const SparseMatrix& a, const std::vector<double>& b, const std::vector<double>& x) {
    std::vector<double> r(b.size());
    multiply(a, x, r);
    for (std::size_t k = 0; k < r.size(); ++k) r[k] = b[k] - r[k];
    const double b_norm = std::sqrt(dot(b, b));
    return b_norm > 0.0 ? std::sqrt(dot(r, r)) / b_norm : 0.0;
}

SolveResult fill_hole(const Grid& grid, const std::vector<std::size_t>& hole, FillMethod method, Tiling tiling,
                      std::vector<std::int32_t>& index, float* heights) {
    HoleSystem system = build_hole_system(grid, hole, method, tiling, index);
    std::vector<double> x(hole.size(), 0.0);
    SolveResult result;
    if (hole.size() <= kDirectSolveLimit) {
        DenseSolver(system.matrix).solve(system.rhs, x);
        result.relative_residual = relative_residual(system.matrix, system.rhs, x);
    } else {
        Level finest;
        finest.rows = grid.rows;
        finest.cols = grid.cols;
        finest.position = hole;
        finest.matrix = std::move(system.matrix);
        std::vector<Level> levels = build_hierarchy(std::move(finest));
        const Preconditioner multigrid = [&levels](const std::vector<double>& r, std::vector<double>& z) {
            v_cycle(levels, 0, r, z);
        };
        result = conjugate_gradients(levels[0].matrix, system.rhs, x, kTolerance,
                                     levels.size() > 1 ? multigrid : jacobi(levels[0].matrix));
    }
    for (std::size_t k = 0; k < hole.size(); ++k) heights[hole[k]] = static_cast<float>(x[k]);
    return result;
}

// ---- Degenerate data -----------------------------------------------------------------------

// The valid points when they all lie on one line of the grid (a single point included), else
// nothing. The test is exact: integer cross products of (row, column) offsets.
std::optional<std::vector<std::size_t>> collinear_valid_points(const Grid& grid) {
    std::vector<std::size_t> valid;
    long long r0 = 0, c0 = 0, dr = 0, dc = 0;  // the first valid point and the direction to the second
    for (std::size_t p = 0; p < grid.size(); ++p) {
        if (grid.unknown(p)) continue;
        const long long r = static_cast<long long>(p / grid.cols);
        const long long c = static_cast<long long>(p % grid.cols);
        if (valid.empty()) {
            r0 = r;
            c0 = c;
        } else if (valid.size() == 1) {
            dr = r - r0;
            dc = c - c0;
        } else if ((r - r0) * dc - (c - c0) * dr != 0) {
            return std::nullopt;
        }
        valid.push_back(p);
    }
    return valid;
}

// One valid point fixes only the constant: both energies reach their minimum, zero, with the
// field constant at its height. Valid points on one line leave the thin plate on a non-periodic
// field free to tilt across the line at no energy, so its fill is undetermined: refused. (The
// membrane's fill, and any fill on a periodic field, is unique once one point is fixed.)
bool fill_degenerate(Heightfield& field, FillMethod method, Tiling tiling) {
    const Grid grid{field.rows, field.cols, field.heights_um.data()};
    const auto line = collinear_valid_points(grid);
    if (!line) return false;
    if (line->size() == 1) {
        std::fill(field.heights_um.begin(), field.heights_um.end(), field.heights_um[line->front()]);
        return true;
    }
    if (method == FillMethod::biharmonic && tiling == Tiling::none)
        throw Error("fill: the " + std::to_string(line->size()) +
                    " valid points lie on one line, which leaves the biharmonic fill free to tilt across it "
                    "(the harmonic fill is defined there)");
    return false;
}

}  // namespace

FillReport fill_missing(Heightfield& field, FillMethod method, Tiling tiling) {
    validate(field, "fill", /*allow_missing=*/true);
    if (fill_degenerate(field, method, tiling)) {
        FillReport report;
        report.method = method;
        report.tiling = tiling;
        report.filled_points = field.size() - 1;
        report.filled_fraction = static_cast<double>(report.filled_points) / static_cast<double>(field.size());
        report.holes = 1;
        report.largest_hole = report.filled_points;
        record_preparation(field, describe(report) + " (one valid point: filled with its height)");
        return report;
    }
    FillReport report;
    report.method = method;
    report.tiling = tiling;
    report.filled_points = count_missing(field);
    report.filled_fraction = static_cast<double>(report.filled_points) / static_cast<double>(field.size());
    const Grid grid{field.rows, field.cols, field.heights_um.data()};
    std::vector<std::int32_t> index;
    const std::vector<std::vector<std::size_t>> holes = find_holes(grid, method, tiling, index);
    // Each hole reads only its own unknowns and the valid points around them, so writing one
    // hole's solution never changes what another hole sees.
    std::vector<SolveResult> results(holes.size());
    try {
        std::vector<std::size_t> small;
        for (std::size_t h = 0; h < holes.size(); ++h) {
            if (holes[h].size() > kDirectSolveLimit)
                results[h] = fill_hole(grid, holes[h], method, tiling, index, field.heights_um.data());
            else
                small.push_back(h);
        }
        parallel_for(small.size(), 64, [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k)
                results[small[k]] = fill_hole(grid, holes[small[k]], method, tiling, index, field.heights_um.data());
        });
    } catch (...) {
        for (const auto& hole : holes)
            for (std::size_t p : hole) field.heights_um[p] = std::numeric_limits<float>::quiet_NaN();
        throw;
    }
    report.holes = holes.size();
    for (std::size_t h = 0; h < holes.size(); ++h) {
        report.largest_hole = std::max(report.largest_hole, holes[h].size());
        report.iterations = std::max(report.iterations, results[h].iterations);
        report.relative_residual = std::max(report.relative_residual, results[h].relative_residual);
    }
    record_preparation(field, describe(report));
    return report;
}

std::string to_string(FillMethod method) { return method == FillMethod::harmonic ? "harmonic" : "biharmonic"; }

FillMethod parse_fill_method(const std::string& text) {
    if (text == "harmonic") return FillMethod::harmonic;
    if (text == "biharmonic") return FillMethod::biharmonic;
    throw Error("'" + text + "' is not a fill method (expected harmonic or biharmonic)");
}

std::string describe(const FillReport& report) {
    char line[320];
    std::snprintf(line, sizeof line, "fill_missing: %zu points (%.3g%%), %s inpainting, %s borders",
                  report.filled_points, 100.0 * report.filled_fraction, to_string(report.method).c_str(),
                  report.tiling == Tiling::periodic ? "periodic" : "non-periodic");
    std::string text = line;
    if (report.filled_points > 0) {
        std::snprintf(line, sizeof line, ", %zu holes (largest %zu points), at most %d CG iterations, residual %.2g",
                      report.holes, report.largest_hole, report.iterations, report.relative_residual);
        text += line;
    }
    return text;
}

}  // namespace glintscope
