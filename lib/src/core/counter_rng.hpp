#pragma once
// Counter-based random numbers: value i of stream s under seed k is a pure function of (k, s, i),
// so any thread can draw any value and a generator gives the same bits on every thread count.
// The mixing is SplitMix64 (Steele, Lea & Flood 2014): its finaliser applied to a Weyl sequence.
#include <cmath>
#include <cstdint>

namespace glintscope {

class CounterRng {
public:
    CounterRng(std::uint64_t seed, std::uint64_t stream) : key_(mix(mix(seed) + stream * kGoldenGamma)) {}

    std::uint64_t bits(std::uint64_t index) const { return mix(key_ + (index + 1) * kGoldenGamma); }

    // Uniform in the open interval (0, 1), so logarithms are finite.
    double uniform(std::uint64_t index) const { return (static_cast<double>(bits(index) >> 11) + 0.5) * 0x1p-53; }

    double uniform(std::uint64_t index, double low, double high) const {
        return low + (high - low) * uniform(index);
    }

    // Two independent standard normals, pair i (Marsaglia & Bray's polar method: a point uniform in
    // the unit disk, no trigonometry). Attempt k uses values 64i + 2k and 64i + 2k + 1; the chance
    // that 32 attempts all miss the disk is 0.2146^32 ≈ 4e-22.
    void normal_pair(std::uint64_t index, double& first, double& second) const {
        for (std::uint64_t attempt = 0; attempt < 32; ++attempt) {
            const double u = 2.0 * uniform(64 * index + 2 * attempt) - 1.0;
            const double v = 2.0 * uniform(64 * index + 2 * attempt + 1) - 1.0;
            const double s = u * u + v * v;
            if (s >= 1.0 || s == 0.0) continue;
            const double scale = std::sqrt(-2.0 * std::log(s) / s);
            first = u * scale;
            second = v * scale;
            return;
        }
        first = second = 0.0;
    }

private:
    static constexpr std::uint64_t kGoldenGamma = 0x9e3779b97f4a7c15ULL;

    static std::uint64_t mix(std::uint64_t z) {
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }

    std::uint64_t key_;
};

// Stream numbers, so that the random numbers of different parts of a surface are independent.
enum RandomStream : std::uint64_t {
    kStreamGaussianNoise = 1,
    kStreamScratches = 2,
    kStreamCdTracks = 3,
};

}  // namespace glintscope
