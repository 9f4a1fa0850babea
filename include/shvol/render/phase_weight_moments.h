#pragma once
/// \file How far the weights of SH-sampled phase functions compound along a render's paths.
///
/// With `"evaluate": "exact"` a scattering event's weight p/pdf has mean 1 and second moment
/// m₂ = ∫ p²/pdf dω ≥ 1 (SHSampledPhase::weightSecondMoment), so a path of k such events carries
/// a weight of second moment m₂^k: almost always small and rarely huge, which renders low in
/// practice long before the mean is wrong (helper 178: HG-like Mie at m₂ = 1.00072, below the
/// per-bounce warning's 1.01, rendered an albedo-1 furnace of σ_t 1000 1.1% low, z = −6: about
/// 240 scattering events per path, 10⁴ to 10⁵ on the longest). The render counts its paths by ln
/// m₂^k, the sum of ln m₂ over their scattering events, and bounds E[m₂^k] over them from below.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace shvol {

struct PhaseWeightMoments {
    /// Bin b holds the paths with ln m₂^k in [b, b + 1)·kBin; the last, all beyond.
    static constexpr double kBin = 1.0 / 16;
    static constexpr int kBins = 129;  // ln m₂^k up to 8 (m₂^k ≈ 2981), then the last bin
    std::array<uint64_t, kBins> paths{};

    void add(double lnM2k) { ++paths[size_t(std::min(double(kBins - 1), lnM2k / kBin))]; }
    void add(const PhaseWeightMoments& o) {
        for (int b = 0; b < kBins; ++b) paths[b] += o.paths[b];
    }
    uint64_t count() const {
        uint64_t n = 0;
        for (uint64_t p : paths) n += p;
        return n;
    }
    /// E[m₂^k] over the paths counted, each at its bin's lower edge: a lower bound (1 for none).
    double meanLowerBound() const {
        const uint64_t n = count();
        if (n == 0) return 1;
        double s = 0;
        for (int b = 0; b < kBins; ++b) s += double(paths[b]) * std::exp(b * kBin);
        return s / double(n);
    }
    /// The share of the paths counted whose m₂^k is at least e^(b·kBin) with b = bin.
    double shareFrom(int bin) const {
        uint64_t beyond = 0;
        for (int b = bin; b < kBins; ++b) beyond += paths[b];
        const uint64_t n = count();
        return n ? double(beyond) / double(n) : 0.0;
    }
};

}  // namespace shvol
