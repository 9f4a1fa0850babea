#pragma once
/// \file Error metrics of an image x against a reference r, over all pixels and channels (N
/// values):
///   RMSE = √(Σ (x − r)² / N),  relMSE = Σ (x − r)² / (r² + ε) / N with ε = 10⁻²,
///   MAE = Σ |x − r| / N,  bias = Σ (x − r) / N with a 95% interval ± 1.96 s/√P over the P = N/3
///   pixels (s the sample standard deviation of a pixel's mean x − r over its channels: pixels
///   are independent, each has its own sample streams, but a pixel's channels share its paths).
/// The z-test (as Mitsuba 3's test suite does it): with the standard errors σ_x, σ_r of each
/// value, z = (x − r)/√(σ_x² + σ_r² + (u_x² + u_r²)/12), p = 2(1 − Φ(|z|)) = erfc(|z|/√2), and the
/// image passes at level α when min p ≥ 1 − (1 − α)^{1/N} (Šidák). u is the float32 spacing at
/// the value (its rounding when stored is uniform over ±u/2): without it, a pixel of constant sky
/// (σ ≈ 0) one float step from the reference failed (p underflowed to 0). Values equal in both
/// images with both σ = 0 (a black void) are left out, as they would only loosen the Šidák
/// level.
#include "shvol/core/image.h"

namespace shvol {

struct ImageMetrics {
    double rmse = 0, relMse = 0, mae = 0, bias = 0, biasHalfWidth95 = 0;
    long long values = 0;  ///< N
};
/// Throws shvol::Error if the sizes differ. Non-finite values count as errors of +∞.
ImageMetrics imageMetrics(const Image& x, const Image& reference);

struct ZTest {
    double minP = 1;       ///< smallest p-value
    double threshold = 0;  ///< Šidák-corrected level
    long long tested = 0;
    bool passed = true;
};
ZTest zTest(const Image& x, const Image& xStdErr, const Image& reference, const Image& refStdErr,
            double alpha = 0.01);
/// Samples per pixel below which a render's standard errors are too poor an estimate for the
/// z-test: unbiased runs of the default scene failed it in every repeat at 2 and 4 spp (p down to
/// 10⁻²⁷⁷; helper 122); it needs about 64, and a few hundred where samples are heavy-tailed
/// (README, `metrics`). The batch warns of runs below it, and tools/report.py marks their cells.
inline constexpr int kZTestReliableSpp = 64;

}  // namespace shvol
