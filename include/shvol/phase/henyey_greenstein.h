#pragma once
/// \file Henyey–Greenstein phase function, the maths (Henyey & Greenstein 1941; pbrt-v4 §11.3.1).
///
/// μ = cos θ is the cosine between the propagation directions before and after scattering, so
/// g > 0 scatters forward (DESIGN.md). g must lie in the open interval (−1, 1).
#include <algorithm>
#include <cmath>

#include "shvol/core/math.h"

namespace shvol {

/// p(μ) = (1 − g²) / (4π (1 + g² − 2gμ)^{3/2}),  ∫ p dω = 1.
/// The base is evaluated as (1 − g)² + 2g(1 − μ) for g ≥ 0 and (1 + g)² − 2g(1 + μ) for g < 0,
/// sums of non-negative terms, so it never cancels to zero or below for |g| → 1. Given the angle's
/// complements (AngleCosine::between(wo, wi)) it keeps its relative accuracy where the lobe is
/// narrower than the rounding of μ (g = 0.999999: the density at the rounded wo·wi was off by
/// 1.3·10⁻³).
double henyeyGreenstein(const AngleCosine& c, double g);
inline double henyeyGreenstein(double cosTheta, double g) {
    return henyeyGreenstein(AngleCosine::of(cosTheta), g);
}

/// Exact inverse of the CDF P(μ) = ∫_{−1}^{μ} 2π p(μ′) dμ′:
///   μ = (1 + g² − s²) / (2g),  s = (1 − g²) / (1 − g + 2gu)            (pbrt-v3 §15.2.3).
/// Evaluated without cancellation or division by g through the equivalent forms
///   1 − μ = (1 − g)(1 − u)(s + 1 − g) / (1 − g + 2gu),
///   1 + μ = (1 + g) u (s + 1 + g) / (1 − g + 2gu),
/// taking whichever of the two is smaller; both reduce to μ = 2u − 1 at g = 0, so the formula
/// stays exact as g → 0 (no isotropic switch is needed) and as |g| → 1. Result clamped to
/// [−1, 1]. \param u uniform in [0, 1]. (HenyeyGreensteinSampler's μ.)
double sampleHenyeyGreensteinCosTheta(double u, double g);
/// The same μ with its complements 1 ∓ μ as the two forms give them (HenyeyGreensteinSampler).
AngleCosine sampleHenyeyGreensteinAngle(double u, double g);

/// The sampler of sampleHenyeyGreensteinCosTheta for one g, with its constants computed once and
/// one division per sample, and the density at the sampled μ in closed form, without a square
/// root:
///   p(μ(u)) = d³ / (4π (1 − g²)²),  d = 1 − g + 2gu,
/// because 1 + g² − 2gμ(u) = s² = ((1 − g²)/d)². It gives p(−1) = (1 − g)/(4π(1 + g)²) at u = 0
/// and p(1) = (1 + g)/(4π(1 − g)²) at u = 1 as products, so it stays accurate as |g| → 1, where
/// henyeyGreenstein(μ) of the rounded μ does not (their ratio is within 4·10⁻¹² of 1 for
/// |g| ≤ 0.99, tested). With cosSin2Pi, HenyeyGreensteinPhase::sample became 2.1× as fast (same
/// run against the former code with three divisions, the density from henyeyGreenstein and
/// sincos, 2026-12-01); build/bench_phase keeps HGAnalytic / HGEvalAndSincos, the share of the
/// closed-form density and cosSin2Pi (1.8×). u must lie in [0, 1] (outside, d can reach 0).
class HenyeyGreensteinSampler {
  public:
    explicit HenyeyGreensteinSampler(double g)
        : oneMinusG_(1 - g),
          onePlusG_(1 + g),
          oneMinusG2_((1 - g) * (1 + g)),
          pdfScale_(1 / (FourPi * oneMinusG2_ * oneMinusG2_)),
          dBase_(g >= 0 ? 1 - g : 1 + g),
          dSlope_(2 * std::abs(g)),
          flip_(g < 0) {}
    struct Sample {
        AngleCosine angle;  ///< μ, clamped to [−1, 1], with 1 ∓ μ from their own forms
        double pdf;
    };
    /// μ and p(μ) for u ∈ [0, 1].
    Sample operator()(double u) const {
        // d = (1 − g) + 2gu for g ≥ 0, (1 + g) + 2|g|(1 − u) for g < 0: sums of non-negative
        // terms (1 − u is exact for the samplers' u), so d³ keeps its relative accuracy.
        const double d = dBase_ + dSlope_ * (flip_ ? 1 - u : u), invD = 1 / d;
        const double s = oneMinusG2_ * invD;
        const double oneMinusMu = std::min(2.0, oneMinusG_ * (1 - u) * (s + oneMinusG_) * invD);
        const double onePlusMu = std::min(2.0, onePlusG_ * u * (s + onePlusG_) * invD);
        const double mu = oneMinusMu <= onePlusMu ? 1 - oneMinusMu : onePlusMu - 1;
        return {{std::clamp(mu, -1.0, 1.0), oneMinusMu, onePlusMu}, d * d * d * pdfScale_};
    }

  private:
    double oneMinusG_, onePlusG_, oneMinusG2_, pdfScale_, dBase_, dSlope_;
    bool flip_;
};

/// The CDF P(μ) = ∫_{−1}^{μ} 2π p(μ′) dμ′ = (1 − g²)/(2g) [b^{−1/2} − 1/(1 + g)], b = 1 + g² − 2gμ,
/// evaluated without division by g or cancellation as
///   P = (1 − g)(1 + μ) / (√b (1 + g + √b))   or   1 − P = (1 + g)(1 − μ) / (√b (1 − g + √b)),
/// the first for μ ≤ g, the second above (b in the non-negative form above). Inverse of
/// sampleHenyeyGreensteinCosTheta. Result in [0, 1].
double henyeyGreensteinCdf(const AngleCosine& c, double g);
inline double henyeyGreensteinCdf(double cosTheta, double g) {
    return henyeyGreensteinCdf(AngleCosine::of(cosTheta), g);
}

}  // namespace shvol
