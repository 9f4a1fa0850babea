#pragma once
/// \file Tabulated phase function: measured or computed values (e.g. Mie theory) at scattering
/// angles θ₀ < θ₁ < … < θₙ₋₁ in degrees, 0 ≤ θᵢ ≤ 180, values fᵢ ≥ 0 in any units.
///
/// Interpolation is piecewise linear in μ = cos θ (not in θ), so that both the normalisation and
/// the CDF are exact closed forms. If the table does not start at 0° or end at 180°, the first and
/// last values are held constant out to μ = 1 and μ = −1 (extra nodes at 0° / 180°). The
/// interpolant f̃ is normalised so that ∫ p dω = 1:
///   p(μ) = f̃(μ) / (2π ∫_{−1}^{1} f̃ dμ′),   normalization() = 1 / (2π ∫ f̃ dμ′).
/// Sampling inverts the piecewise-quadratic CDF exactly (PiecewiseLinear1D), so pdf = eval.
/// μ = cos θ = wo·wi as for every phase function (DESIGN.md): θ = 0 is forward.
#include <memory>
#include <string>
#include <vector>

#include "shvol/core/math.h"
#include "shvol/phase/phase_sample.h"
#include "shvol/phase/piecewise_linear_1d.h"

namespace shvol {

class TabulatedPhase {
  public:
    static constexpr const char* kName = "tabulated";
    /// \param anglesDeg strictly increasing, within [0, 180], at least 2, with distinct cosines.
    /// \param values finite, ≥ 0, not all zero (after extension, with a non-zero integral).
    /// \param source where the table came from (a file name), for messages.
    /// Throws std::invalid_argument if the table is invalid (readPhaseTableCsv checks first and
    /// reports the line).
    TabulatedPhase(const std::vector<double>& anglesDeg, const std::vector<double>& values,
                   std::string source = "");

    /// p(μ) = normalization() · f̃(μ).
    double evalCos(double cosTheta) const;
    double eval(const Vec3& wo, const Vec3& wi) const { return evalCos(wo.dot(wi)); }
    /// Exact sampler, so pdf = eval.
    double pdf(const Vec3& wo, const Vec3& wi) const { return eval(wo, wi); }
    /// cos θ from the exact inverse of the piecewise-quadratic CDF, φ = 2π u₂ around wo.
    PhaseSample sample(const Vec3& wo, const Vec2& u) const;

    /// Factor applied to the table's values: 1 / (2π ∫ f̃ dμ).
    double normalization() const { return data_->normalization; }
    const std::string& source() const { return data_->source; }
    /// The interpolant over μ (nodes ascending in μ, values as given).
    const PiecewiseLinear1D& table() const { return data_->table; }

  private:
    struct Data {
        PiecewiseLinear1D table;
        double normalization;
        std::string source;
    };
    std::shared_ptr<const Data> data_;  // shared by copies: PhaseFunction stays cheap to copy
};

}  // namespace shvol
