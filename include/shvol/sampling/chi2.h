#pragma once
/// \file Chi-square goodness-of-fit test of a directional sampler over the sphere, after
/// Mitsuba 3's `mitsuba.chi2.ChiSquareTest` (and Mitsuba 0.5 / Nori's chi2test).
///
/// The sphere is split into zBins × phiBins equal-area cells, uniform in z = cos θ ∈ [−1, 1]
/// and φ ∈ [0, 2π) (dω = dz dφ). N = sampleCount samples are histogrammed; the expected count of
/// a cell is Eᵢ = N ∫_cell pdf(ω) dω, integrated by nested adaptive Simpson quadrature in (θ, φ)
/// with dω = sin θ dθ dφ, which also handles the 1/sin θ poles of lat-long map pdfs (each cell
/// starts on an 8×8 sub-grid and refines to a relative error ≈ 1e-7, so peaked pdfs such as
/// Henyey–Greenstein with g = 0.99 are integrated accurately). Cells are sorted by Eᵢ; cells with
/// Eᵢ < minExpected are merged into one pooled cell (the following cells are also merged while the
/// pool is still below minExpected), and the pool is tested if its expected count reaches
/// minExpected. A cell with observed > 0 and expected == 0 fails at once, as does one whose
/// expected count is negative or not finite (even −10⁻¹⁷ from a difference of CDFs: clamp such
/// rounding where it is computed).
///   χ² = Σ (Oᵢ − Eᵢ)² / Eᵢ over the tested cells,   dof = (tested cells) − 1,
///   p = Q(dof/2, χ²/2)  (regularised upper incomplete gamma, boost::math::gamma_q).
/// With the Šidák correction for numTests tests the test passes iff p > 1 − (1 − α)^(1/numTests).
/// Samples that come back empty (std::nullopt) or non-finite count towards N but fall in no cell;
/// a non-finite one fails the test, an empty one unless Chi2Options::allowFailedSamples.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "shvol/core/math.h"
#include "shvol/core/rng.h"

namespace shvol {

struct Chi2Options {
    int zBins = 40;
    int phiBins = 80;
    long long sampleCount = 1000000;
    double alpha = 0.01;  ///< significance level of the whole family of tests
    int numTests = 1;     ///< size of the family (Šidák correction)
    double minExpected = 5;
    uint64_t seed = 1;  ///< the sampler is driven by Rng(seed, 0)
    /// Samples that come back empty fail the test, however few, unless allowed (a BSDF's samples
    /// below the horizon are legitimately empty); non-finite ones always do: a fraction f of them
    /// adds only about f²·N to χ², so 1% NaN of 10⁶ samples passed (helper 89), and allowing
    /// the empty ones let NaN hide among them (helper 90).
    bool allowFailedSamples = false;
};

struct Chi2Result {
    bool passed = false;
    double pValue = 0;
    double statistic = 0;
    int dof = 0;
    std::string report;      ///< statistic, dof, p, pdf integral, failed samples and worst cells
    double pdfIntegral = 0;  ///< ∫ pdf dω over the sphere (should be ≈ 1)
    long long failedSamples = 0;     ///< samples that were std::nullopt or not finite
    long long nonFiniteSamples = 0;  ///< of those, not finite
    long long nonUnitSamples = 0;    ///< finite directions whose length is not 1 (± 10⁻⁶)
};

/// Runs the test. \param sample draws one direction (unit vector) from the generator, or
/// std::nullopt for a failed sample. A direction that is not finite, or whose length is not 1
/// within 10⁻⁶ (the integrator uses directions as they come), fails the test. \param pdf the
/// claimed solid-angle density of sample.
Chi2Result chi2TestSphere(const std::function<std::optional<Vec3>(Rng&)>& sample,
                          const std::function<double(const Vec3&)>& pdf,
                          const Chi2Options& opt = {});

/// The same test with the expected probability of each cell given exactly, as
/// cellProbability(z0, z1, φ0, φ1) = ∫_cell pdf dω. For samplers whose density is piecewise
/// constant on a fine grid (hierarchical warps), where quadrature would chase every jump.
Chi2Result chi2TestSphereCells(
    const std::function<std::optional<Vec3>(Rng&)>& sample,
    const std::function<double(double z0, double z1, double phi0, double phi1)>& cellProbability,
    const Chi2Options& opt = {});

/// The χ² of counts binned by the caller (1D and 2D samplers, free-flight distances): observed
/// against expected counts per cell, with chi2TestSphere's pooling, statistic and Šidák
/// threshold (opt.alpha, numTests and minExpected; the binning and sampling options are unused).
/// A cell with observed > 0 and expected 0, an observed or expected count that is negative or
/// not finite, or options out of their range (alpha outside (0, 1), numTests < 1,
/// minExpected ≤ 0) fail at once. cellName(i) names cell i in the report ("cell i" without it).
Chi2Result chi2TestCounts(const std::vector<double>& observed, const std::vector<double>& expected,
                          const Chi2Options& opt = {},
                          const std::function<std::string(size_t)>& cellName = {});

/// Cells for a lobe too narrow for equal-area cells (HG g = 0.999999 is about 10⁻¹² wide in
/// 1 − μ): a sample's distance d ∈ [0, 2] from the lobe's pole (1 − cos of the angle, from
/// |w − pole|²/2 without the rounding of a dot product) becomes the cell coordinate
/// z' = 2 (ln d − ln dMin)/(ln 2 − ln dMin) − 1, equal steps in ln d from dMin to 2, with d < dMin
/// in the first cell; chi2TestSphereCells bins z' (and φ about the pole) as it bins z.
struct LogDistanceCells {
    double dMin = 1e-15;
    /// z' of d (not −1 itself: at the pole the direction binned would lose its φ).
    double z(double d) const {
        const double s0 = std::log(dMin), s1 = std::log(2.0);
        return d <= dMin ? -1 + 1e-9 : std::min(1.0, 2 * (std::log(d) - s0) / (s1 - s0) - 1);
    }
    /// d of z', 0 at z' ≤ −1.
    double d(double z) const {
        const double s0 = std::log(dMin), s1 = std::log(2.0);
        return z <= -1 ? 0.0 : std::exp(s0 + (z + 1) / 2 * (s1 - s0));
    }
};

/// ∫_{S²} f dω, summed over zBins × phiBins (z, φ) cells, each integrated by the same nested
/// adaptive Simpson rule as the chi² expected counts (relative accuracy ≈ 1e-7 per cell).
double integrateOverSphere(const std::function<double(const Vec3&)>& f, int zBins = 40,
                           int phiBins = 80);

}  // namespace shvol
