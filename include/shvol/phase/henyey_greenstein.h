#pragma once
/// \file Henyey–Greenstein phase function, the maths (Henyey & Greenstein 1941; pbrt-v4 §11.3.1).
///
/// μ = cos θ is the cosine between the propagation directions before and after scattering, so
/// g > 0 scatters forward (DESIGN.md). g must lie in the open interval (−1, 1).
namespace shvol {

/// p(μ) = (1 − g²) / (4π (1 + g² − 2gμ)^{3/2}),  ∫ p dω = 1.
/// The base is evaluated as (1 − g)² + 2g(1 − μ) for g ≥ 0 and (1 + g)² − 2g(1 + μ) for g < 0,
/// sums of non-negative terms, so it never cancels to zero or below for |g| → 1.
double henyeyGreenstein(double cosTheta, double g);

/// Exact inverse of the CDF P(μ) = ∫_{−1}^{μ} 2π p(μ′) dμ′:
///   μ = (1 + g² − s²) / (2g),  s = (1 − g²) / (1 − g + 2gu)            (pbrt-v3 §15.2.3).
/// Evaluated without cancellation or division by g through the equivalent forms
///   1 − μ = (1 − g)(1 − u)(s + 1 − g) / (1 − g + 2gu),
///   1 + μ = (1 + g) u (s + 1 + g) / (1 − g + 2gu),
/// taking whichever of the two is smaller; both reduce to μ = 2u − 1 at g = 0, so the formula
/// stays exact as g → 0 (no isotropic switch is needed) and as |g| → 1. Result clamped to
/// [−1, 1]. \param u uniform in [0, 1).
double sampleHenyeyGreensteinCosTheta(double u, double g);

/// The CDF P(μ) = ∫_{−1}^{μ} 2π p(μ′) dμ′ = (1 − g²)/(2g) [b^{−1/2} − 1/(1 + g)], b = 1 + g² − 2gμ,
/// evaluated without division by g or cancellation as
///   P = (1 − g)(1 + μ) / (√b (1 + g + √b))   or   1 − P = (1 + g)(1 − μ) / (√b (1 − g + √b)),
/// the first for μ ≤ g, the second above (b in the non-negative form above). Inverse of
/// sampleHenyeyGreensteinCosTheta. Result in [0, 1].
double henyeyGreensteinCdf(double cosTheta, double g);

}  // namespace shvol
