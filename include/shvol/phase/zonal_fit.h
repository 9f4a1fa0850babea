#pragma once
/// \file Zonal SH fit of a phase function p(μ), μ = cos θ, and its quality.
///
///   p(μ) ≈ p̃(μ) = Σ_{l<n} w_l p_l y_l^0(μ),   p_l = 2π ∫_{−1}^{1} p(μ) y_l^0(μ) dμ,
/// (DESIGN.md; for Henyey–Greenstein p_l = g^l √((2l+1)/4π)). The projection integral is computed
/// by 16-point Gauss–Legendre panels in θ, geometrically graded towards θ = 0 and θ = π down to
/// 1e−7 rad, so that lobes as narrow as HG g = 0.999 are resolved.
///
/// Positivity. A truncated series of a peaked lobe rings and goes negative (HG g = 0.99 at order
/// 16 reaches about −10% of its peak). The optional window w_l damps the high bands (Sloan 2008,
/// "Stupid spherical harmonics tricks", §windowing): Hann w_l = ½(1 + cos(πl/n)), Lanczos
/// w_l = sinc(l/n). Both keep w_0 = 1, hence ∫p̃ = 1, and trade sharpness (L2 error) for less
/// ringing. No window makes p̃ positive for every input; the samplers clamp what remains (see
/// sampling/zonal_sh_sampler.h), and the fit reports the minimum so users see it.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "shvol/core/math.h"

namespace shvol {

enum class SHWindow { None, Hann, Lanczos };
SHWindow shWindowFromName(const std::string& name);  ///< "none", "hann", "lanczos"
const char* shWindowName(SHWindow w);

struct ZonalFit {
    std::vector<double> p;  ///< windowed coefficients w_l p_l, l < order
    SHWindow window = SHWindow::None;
    double energyFraction = 0;  ///< Σ_{l<n} p_l² / ∫p² dω (Gautron 2004 eq. 15; unwindowed p_l)
    double l2Error = 0;         ///< (∫ (p − p̃)² dω)^{1/2}
    double relativeL2Error = 0;  ///< l2Error / (∫ p² dω)^{1/2}
    /// The next three over the quadrature nodes, the poles and the corners (a table's nodes):
    /// narrow dips of p̃ between nodes are missed (in helper 142's search of 2·10⁶ angles, at
    /// most 2.6·10⁻⁴ of the peak deeper: below the ringing threshold of 10⁻³ of it).
    double maxError = 0;   ///< max_μ |p − p̃|
    double minValue = 0;   ///< min_μ p̃ (negative: ringing)
    double peakValue = 0;  ///< max_μ p, for scale
    double energy = 0;     ///< ∫ p² dω
};

/// Fits p at the given order (number of bands, 1 … 1024). p is given the angle of each
/// quadrature node with its cosine's complements (AngleCosine::ofAngle), so that a lobe narrower
/// than μ's rounding near ±1 can be evaluated where it is: from μ alone the coefficients of HG
/// were off by 1.5·10⁻⁶ of themselves at g = 0.999999 and by 3.5·10⁻¹⁰ at 0.9999, from the angle
/// by 1.1·10⁻¹¹ and 2.6·10⁻¹³. A generic lambda matches both overloads: name its parameter type.
/// `corners`: angles θ (radians) where p is not smooth, at which the quadrature's panels end (a
/// table's nodes, PhaseFunction::corners: across them the fit of a table was off by up to
/// 1.8·10⁻⁴ in p_0 and 6% in its printed error; helper 110).
ZonalFit fitZonal(const std::function<double(const AngleCosine&)>& p, int order,
                  SHWindow window = SHWindow::None, const std::vector<double>& corners = {});
/// The same for p(μ), for functions that μ resolves (polynomials, lobes much wider than 10⁻⁴
/// rad, e.g. HG with |g| ≤ 0.99).
ZonalFit fitZonal(const std::function<double(double mu)>& p, int order,
                  SHWindow window = SHWindow::None);

/// What a scene asks of a fit, with the two automatic choices:
///  - order 0 ("auto"): the lowest order ≤ kMaxAutoOrder whose relative L2 error is at most
///    `tolerance`, else kMaxAutoOrder (the fit reports the error it reaches). The error of every
///    order comes from one unwindowed fit at kMaxAutoOrder by Parseval: ε_n² ∫p² = ∫p² − Σ_{l<n}
///    p_l² + Σ_{l<n} (1 − w_l)² p_l², summed as (∫p² − Σ_{l<L} p_l²) + Σ_{n≤l<L} p_l² + Σ_{l<n}
///    (1 − w_l)² p_l² (L = kMaxAutoOrder), the first term 0 within its rounding noise, so that
///    tolerances down to 10⁻⁹ can be met.
///  - window nullopt ("auto"): no window if the unwindowed fit nowhere dips below −10⁻³ of the
///    function's peak (so a function the order represents exactly, such as Rayleigh from order
///    3, stays exact, and shallow ringing is left to the samplers' clamping), else Hann.
///    With both automatic, the order is the lowest that meets the tolerance unwindowed if that
///    fit does not dip so, else the lowest that meets it with Hann. When no order meets it with
///    Hann, the unwindowed fit is kept (the lowest order meeting the tolerance; when none does,
///    the fit at kMaxAutoOrder, the one of least error), and the samplers clamp its dips.
struct ZonalFitRequest {
    static constexpr int kMaxAutoOrder = 256;
    int order = 0;  ///< 0: auto (the default)
    double tolerance = 0.01;
    std::optional<SHWindow> window;  ///< nullopt: auto
};

/// The fit a request names.
ZonalFit fitZonal(const std::function<double(const AngleCosine&)>& p,
                  const ZonalFitRequest& request, const std::vector<double>& corners = {});
ZonalFit fitZonal(const std::function<double(double mu)>& p, const ZonalFitRequest& request);

/// Relative L2 error of the order-n fit with window w by Parseval (formula above), from the
/// unwindowed coefficients pFull (at least n of them) and ∫p² dω.
double relativeL2ErrorByParseval(const std::vector<double>& pFull, double energy, int n,
                                 SHWindow w);

/// Edges of the θ panels for quadrature over a phase function: 0, then geometric steps (ratio
/// 1.25) from 1e−7 rad up to π/2, mirrored down to π, so lobes as narrow as HG g = 0.999 are
/// resolved at either pole; and the function's `corners` in (0, π), ascending, without repeats.
std::vector<double> gradedThetaEdges(const std::vector<double>& corners = {});

}  // namespace shvol
