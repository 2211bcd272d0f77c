#pragma once
// The ξ3 values at which the FFT lobe transforms R*. OHS and R-OHS have ξ3 = 2: one transform.
// For GHS, R-GHS and Kirchhoff ξ3 = ψ·n changes across the image, so R̃* is transformed at the
// nodes ξ = k/M and each sub-pixel interpolates cubically (Lagrange, four nearest nodes) to its
// own ξ3. R̃* is linear in R*, so this interpolates every sample's phasor e^{−iαξ},
// α = 2π(H − H̄)/λ; the Lagrange remainder (Hermite–Genocchi form, valid for complex functions)
// on the central interval is ≤ α⁴ (3/128) Δ⁴ with Δ = 1/M, hence for every v
//   |δR̃*(v)| ≤ (3/128) Δ⁴ ∫|w| α⁴ ds = ε ∫|w| ds   when   Δ = (ε / ((3/128) ⟨α⁴⟩_|w|))^{1/4},
// i.e. ε times a flat mirror's peak |R̃*|. (Kirchhoff: ∫|w| becomes ∫|w|(1 + |ψ̄·H'|/ψ·n).)
// The nodes sit on the fixed lattice k/M, so a pixel's value does not depend on which other
// pixels the image holds: swapping ω_i and ω_o reuses the same nodes, keeping reciprocity exact.
#include "glintscope/optics/diffraction_model.hpp"
#include "wave/footprint_grid.hpp"

namespace glintscope {

struct Xi3Slices {
    int nodes_per_unit = 0;  // M; 0 when ξ3 is the constant `constant_xi3`
    double constant_xi3 = 2.0;
    int first = 0;           // node indices first … last
    int last = 0;

    int count() const { return last - first + 1; }
    double node(int index) const { return nodes_per_unit ? double(index) / nodes_per_unit : constant_xi3; }
    // The weight of node `index` in the value at ξ3 (zero unless it is one of the four nearest).
    double weight(int index, double xi3) const;
    // The node indices [lowest, highest] with a possibly non-zero weight at ξ3.
    int lowest_node(double xi3) const;
    int highest_node(double xi3) const;
};

// Nodes for ξ3 ∈ [xi3_min, xi3_max] with the interpolation error bound `phase_error` (ε above).
// Throws Error if more than `max_count` nodes would be needed.
Xi3Slices choose_xi3_slices(DiffractionModel model, const FootprintSamples& samples, double lambda_um,
                            double xi3_min, double xi3_max, double phase_error, int max_count);

}  // namespace glintscope
