// Form removal: the least-squares polynomial of the valid heights is subtracted (the tilt of a
// mounted sample, the curvature of a cylinder or sphere), leaving the microgeometry.
//
// The basis is P_i(u) P_j(v), i + j ≤ order, with Legendre polynomials P_n and u, v ∈ [−1, 1]
// the sample centres scaled about the field centre. On a full grid these are nearly orthogonal,
// so the normal equations stay well conditioned up to kMaxFormOrder where monomials x^i y^j in
// µm would not. Because the grid is a tensor product, the normal matrix
//   G[(i,j),(k,l)] = Σ_rows P_j(v_r) P_l(v_r) Σ_valid columns P_i(u_c) P_k(u_c)
// is built from per-row sums, about 30 operations per sample even at order 6; the rows are
// combined in order in long double, and the small system is solved by Cholesky.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/prepare/prepare.hpp"

namespace glintscope {
namespace {

constexpr std::size_t kRowsPerChunk = 64;

// P_0(t) .. P_order(t) by the three-term recurrence (n + 1) P_{n+1} = (2n + 1) t P_n − n P_{n−1}.
void legendre(int order, double t, double* p) {
    p[0] = 1.0;
    if (order >= 1) p[1] = t;
    for (int n = 1; n < order; ++n) p[n + 1] = ((2 * n + 1) * t * p[n] - n * p[n - 1]) / (n + 1);
}

// P_n(0) and P_n'(0), from P_{n+1}' = P_{n−1}' + (2n + 1) P_n.
double legendre_at_zero(int n) {
    std::vector<double> p(static_cast<std::size_t>(n) + 1);
    legendre(n, 0.0, p.data());
    return p[static_cast<std::size_t>(n)];
}

double legendre_slope_at_zero(int n) {
    std::vector<double> p(static_cast<std::size_t>(n) + 2), dp(static_cast<std::size_t>(n) + 2, 0.0);
    legendre(n + 1, 0.0, p.data());
    if (n >= 1) dp[1] = 1.0;
    for (int k = 1; k < n; ++k) dp[k + 1] = dp[k - 1] + (2 * k + 1) * p[k];
    return dp[static_cast<std::size_t>(n)];
}

// Per-sample scaled coordinate: u_c = (c − (n − 1)/2) / ((n − 1)/2), or 0 for a single sample.
double scaled(int index, int count) {
    if (count <= 1) return 0.0;
    const double half = 0.5 * (count - 1);
    return (index - half) / half;
}

// Solves G a = b (G symmetric positive definite, size n) by Cholesky in long double. Returns
// false when a pivot is not clearly positive: the data do not determine every coefficient.
bool solve_normal_equations(std::vector<long double> g, std::vector<long double> b, int n,
                            std::vector<double>& solution) {
    const auto at = [&](int i, int j) -> long double& { return g[static_cast<std::size_t>(i) * n + j]; };
    for (int j = 0; j < n; ++j) {
        const long double original = at(j, j);
        long double d = original;
        for (int k = 0; k < j; ++k) d -= at(j, k) * at(j, k);
        if (!(d > 1e-12L * original)) return false;
        at(j, j) = std::sqrt(d);
        for (int i = j + 1; i < n; ++i) {
            long double sum = at(i, j);
            for (int k = 0; k < j; ++k) sum -= at(i, k) * at(j, k);
            at(i, j) = sum / at(j, j);
        }
    }
    for (int i = 0; i < n; ++i) {
        long double sum = b[static_cast<std::size_t>(i)];
        for (int k = 0; k < i; ++k) sum -= at(i, k) * b[static_cast<std::size_t>(k)];
        b[static_cast<std::size_t>(i)] = sum / at(i, i);
    }
    for (int i = n - 1; i >= 0; --i) {
        long double sum = b[static_cast<std::size_t>(i)];
        for (int k = i + 1; k < n; ++k) sum -= at(k, i) * b[static_cast<std::size_t>(k)];
        b[static_cast<std::size_t>(i)] = sum / at(i, i);
    }
    solution.assign(b.begin(), b.end());
    return true;
}

}  // namespace

FormReport remove_form(Heightfield& field, int order) {
    if (order < 0 || order > kMaxFormOrder)
        throw Error("remove-form: polynomial order " + std::to_string(order) + " is outside 0.." +
                    std::to_string(kMaxFormOrder));
    validate(field, "remove-form", /*allow_missing=*/true);
    const int rows = field.rows;
    const int cols = field.cols;
    const int degrees = order + 1;
    FormReport report;
    report.order = order;
    for (int total = 0; total <= order; ++total)
        for (int j = 0; j <= total; ++j) report.terms.push_back({total - j, j, 0.0});
    const int n_terms = static_cast<int>(report.terms.size());

    std::vector<double> pu(static_cast<std::size_t>(cols) * degrees);
    std::vector<double> pv(static_cast<std::size_t>(rows) * degrees);
    for (int c = 0; c < cols; ++c) legendre(order, scaled(c, cols), &pu[static_cast<std::size_t>(c) * degrees]);
    // Map view: row 0 is the largest y, so v runs opposite to the row index.
    for (int r = 0; r < rows; ++r)
        legendre(order, -scaled(r, rows), &pv[static_cast<std::size_t>(r) * degrees]);

    // Per row: Σ_c P_i P_k (i, k ≤ order), Σ_c P_i h, and the valid count, over valid columns.
    const std::size_t row_stride = static_cast<std::size_t>(degrees) * degrees + degrees + 1;
    std::vector<double> row_sums(static_cast<std::size_t>(rows) * row_stride, 0.0);
    parallel_for(static_cast<std::size_t>(rows), kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            double* sums = &row_sums[r * row_stride];
            for (int c = 0; c < cols; ++c) {
                const float h = field.at(static_cast<int>(r), c);
                if (std::isnan(h)) continue;
                const double* p = &pu[static_cast<std::size_t>(c) * degrees];
                for (int i = 0; i < degrees; ++i) {
                    for (int k = i; k < degrees; ++k) sums[i * degrees + k] += p[i] * p[k];
                    sums[degrees * degrees + i] += p[i] * h;
                }
                sums[row_stride - 1] += 1.0;
            }
            for (int i = 0; i < degrees; ++i)
                for (int k = 0; k < i; ++k) sums[i * degrees + k] = sums[k * degrees + i];
        }
    });
    std::vector<long double> g(static_cast<std::size_t>(n_terms) * n_terms, 0.0L);
    std::vector<long double> b(static_cast<std::size_t>(n_terms), 0.0L);
    for (int r = 0; r < rows; ++r) {
        const double* sums = &row_sums[static_cast<std::size_t>(r) * row_stride];
        const double* q = &pv[static_cast<std::size_t>(r) * degrees];
        report.fitted_points += static_cast<std::size_t>(sums[row_stride - 1]);
        for (int a = 0; a < n_terms; ++a) {
            const FormTerm& ta = report.terms[static_cast<std::size_t>(a)];
            b[static_cast<std::size_t>(a)] += static_cast<long double>(q[ta.j]) * sums[degrees * degrees + ta.i];
            for (int c = 0; c < n_terms; ++c) {
                const FormTerm& tc = report.terms[static_cast<std::size_t>(c)];
                g[static_cast<std::size_t>(a) * n_terms + c] +=
                    static_cast<long double>(q[ta.j]) * q[tc.j] * sums[ta.i * degrees + tc.i];
            }
        }
    }
    std::vector<double> coefficients;
    if (report.fitted_points < static_cast<std::size_t>(n_terms) ||
        !solve_normal_equations(std::move(g), std::move(b), n_terms, coefficients))
        throw Error("remove-form: the " + std::to_string(report.fitted_points) +
                    " valid points do not determine a polynomial of order " + std::to_string(order) +
                    " (too few distinct rows or columns); use a lower order");
    for (int a = 0; a < n_terms; ++a)
        report.terms[static_cast<std::size_t>(a)].coefficient_um = coefficients[static_cast<std::size_t>(a)];

    // Subtract, and gather Σ form, Σ form², Σ residual² per row for the report.
    std::vector<double> row_totals(static_cast<std::size_t>(rows) * 3, 0.0);
    parallel_for(static_cast<std::size_t>(rows), kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        std::vector<double> along_x(static_cast<std::size_t>(degrees));
        for (std::size_t r = begin; r < end; ++r) {
            const double* q = &pv[r * degrees];
            std::fill(along_x.begin(), along_x.end(), 0.0);
            for (const FormTerm& term : report.terms)
                along_x[static_cast<std::size_t>(term.i)] += term.coefficient_um * q[term.j];
            double* totals = &row_totals[r * 3];
            for (int c = 0; c < cols; ++c) {
                float& h = field.at(static_cast<int>(r), c);
                if (std::isnan(h)) continue;
                const double* p = &pu[static_cast<std::size_t>(c) * degrees];
                double form = 0.0;
                for (int i = 0; i < degrees; ++i) form += along_x[static_cast<std::size_t>(i)] * p[i];
                h = static_cast<float>(h - form);
                totals[0] += form;
                totals[1] += form * form;
                totals[2] += static_cast<double>(h) * h;
            }
        }
    });
    long double sum = 0.0L, sum_squares = 0.0L, residual_squares = 0.0L;
    for (int r = 0; r < rows; ++r) {
        sum += row_totals[static_cast<std::size_t>(r) * 3];
        sum_squares += row_totals[static_cast<std::size_t>(r) * 3 + 1];
        residual_squares += row_totals[static_cast<std::size_t>(r) * 3 + 2];
    }
    const auto count = static_cast<long double>(report.fitted_points);
    report.mean_um = static_cast<double>(sum / count);
    report.rms_removed_um =
        static_cast<double>(std::sqrt(std::max(0.0L, sum_squares / count - (sum / count) * (sum / count))));
    report.rms_residual_um = static_cast<double>(std::sqrt(residual_squares / count));

    report.centre_um = field.centre_um();
    report.u_scale_um = cols > 1 ? 0.5 * (cols - 1) * field.texel_um : field.texel_um;
    report.v_scale_um = rows > 1 ? 0.5 * (rows - 1) * field.dy_um() : field.dy_um();
    for (const FormTerm& term : report.terms) {
        report.slope_x += term.coefficient_um * legendre_slope_at_zero(term.i) * legendre_at_zero(term.j) /
                          report.u_scale_um;
        report.slope_y += term.coefficient_um * legendre_at_zero(term.i) * legendre_slope_at_zero(term.j) /
                          report.v_scale_um;
    }
    // A tilt or curvature taken off a periodic tile leaves a step at its borders; a mean does not.
    report.ended_periodicity = order > 0 && field.periodic;
    if (report.ended_periodicity) field.periodic = false;
    record_preparation(field, describe(report));
    return report;
}

int parse_form_order(const std::string& text) {
    if (text == "mean") return 0;
    if (text == "plane") return 1;
    const std::string prefix = "poly:";
    if (text.rfind(prefix, 0) == 0 && text.size() > prefix.size()) {
        const std::string digits = text.substr(prefix.size());
        if (digits.find_first_not_of("0123456789") == std::string::npos && digits.size() <= 2) {
            const int order = std::stoi(digits);
            if (order <= kMaxFormOrder) return order;
        }
    }
    throw Error("'" + text + "' is not a form (expected mean, plane or poly:N with N in 0.." +
                std::to_string(kMaxFormOrder) + ")");
}

std::string describe(const FormReport& report) {
    char line[320];
    const char* name = report.order == 0 ? "mean" : report.order == 1 ? "plane" : nullptr;
    std::string kind = name ? name : "polynomial order " + std::to_string(report.order);
    std::snprintf(line, sizeof line,
                  "remove_form: %s (%zu terms) over %zu points: mean %.6g um, slope x %.4g, y %.4g at the centre; "
                  "form rms %.4g um removed, residual rms %.4g um",
                  kind.c_str(), report.terms.size(), report.fitted_points, report.mean_um, report.slope_x,
                  report.slope_y, report.rms_removed_um, report.rms_residual_um);
    return line + std::string(report.ended_periodicity ? "; the field is no longer periodic" : "");
}

}  // namespace glintscope
