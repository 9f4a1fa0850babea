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
#include <string>
#include <vector>

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
    double maxError = 0;         ///< max_μ |p − p̃| on the quadrature nodes
    double minValue = 0;         ///< min_μ p̃ (negative: ringing)
    double peakValue = 0;        ///< max_μ p, for scale
};

/// Fits p at the given order (number of bands, 1 … 1024).
ZonalFit fitZonal(const std::function<double(double mu)>& p, int order,
                  SHWindow window = SHWindow::None);

}  // namespace shvol
