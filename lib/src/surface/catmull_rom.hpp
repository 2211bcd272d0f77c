#pragma once
// The Catmull–Rom cubic convolution kernel (Keys a = −1/2) of the shared interpolant
// (conventions.md "Heightfield interpolation"), for the code that applies it along one axis.
namespace glintscope {

// Weights for the four samples at offsets −1, 0, 1, 2 around a fractional position t ∈ [0, 1),
// and their derivatives d/dt.
struct CubicWeights {
    double w[4];
    double dw[4];
};

inline CubicWeights catmull_rom(double t) {
    const double t2 = t * t;
    const double t3 = t2 * t;
    return {{0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0), 0.5 * (-3.0 * t3 + 4.0 * t2 + t),
             0.5 * (t3 - t2)},
            {0.5 * (-3.0 * t2 + 4.0 * t - 1.0), 0.5 * (9.0 * t2 - 10.0 * t), 0.5 * (-9.0 * t2 + 8.0 * t + 1.0),
             0.5 * (3.0 * t2 - 2.0 * t)}};
}

}  // namespace glintscope
