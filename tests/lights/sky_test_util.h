#pragma once
// Helpers shared by the sky-hierarchy and product-sampler tests.
#include <gtest/gtest.h>

#include <functional>
#include <utility>
#include <vector>

#include "shvol/core/image.h"
#include "shvol/sampling/chi2.h"

namespace shvol::test {

/// Exact cell probabilities of a density that is constant on each leaf of a 2^levels × 2^levels
/// (z, φ) grid: the leaf masses come from pdfAtLeafCentre(direction) × leaf area, and a chi² cell
/// [z0, z1] × [φ0, φ1] collects every leaf in proportion to its overlap. That the density is
/// constant on a leaf is asserted, not assumed, at two points off the centre of every 61st leaf
/// (helper 179: a density varying within leaves would have got wrong expected counts).
class GridProbability {
  public:
    GridProbability(int levels, const std::function<double(const Vec3&)>& pdfAtLeafCentre)
        : n_(1 << levels), mass_(size_t(n_) * n_) {
        const double hz = 2.0 / n_, hp = TwoPi / n_;
        for (int iz = 0; iz < n_; ++iz)
            for (int ip = 0; ip < n_; ++ip) {
                const Vec3 w = sphericalDirection(-1 + (iz + 0.5) * hz, (ip + 0.5) * hp);
                const double pdf = pdfAtLeafCentre(w);
                mass_[size_t(iz) * n_ + ip] = pdf * hz * hp;
                if ((iz * n_ + ip) % 61 == 0)
                    for (const auto& [fz, fp] : {std::pair{0.1, 0.9}, std::pair{0.8, 0.2}})
                        EXPECT_NEAR(pdfAtLeafCentre(
                                        sphericalDirection(-1 + (iz + fz) * hz, (ip + fp) * hp)),
                                    pdf, 1e-12 * pdf)
                            << "leaf " << iz << ", " << ip;
            }
    }
    /// Σ of all leaf masses (∫ pdf dω; 1 for a normalised density).
    double total() const {
        double s = 0;
        for (double m : mass_) s += m;
        return s;
    }
    double operator()(double z0, double z1, double p0, double p1) const {
        const double hz = 2.0 / n_, hp = TwoPi / n_;
        const int a0 = std::max(0, int((z0 + 1) / hz)), a1 = std::min(n_ - 1, int((z1 + 1) / hz));
        const int b0 = std::max(0, int(p0 / hp)), b1 = std::min(n_ - 1, int(p1 / hp));
        double s = 0;
        for (int iz = a0; iz <= a1; ++iz) {
            const double oz = std::min(z1, -1 + (iz + 1) * hz) - std::max(z0, -1 + iz * hz);
            if (!(oz > 0)) continue;
            for (int ip = b0; ip <= b1; ++ip) {
                const double op = std::min(p1, (ip + 1) * hp) - std::max(p0, ip * hp);
                if (op > 0) s += mass_[size_t(iz) * n_ + ip] * (oz / hz) * (op / hp);
            }
        }
        return s;
    }

  private:
    int n_;
    std::vector<double> mass_;
};

/// A W×H lat-long sky: a blue gradient, a dim ground and a disc of radiance `sunRadiance` and
/// angular radius `sunRadius` around `sun`, each pixel the average over 8×8 sub-samples (so a
/// small sun keeps its energy). Directions through the Blender mapping, rotation 0.
Image testSky(int W, const Vec3& sun, double sunRadius, double sunRadiance);

}  // namespace shvol::test
