#pragma once
/// \file Error metrics of an image x against a reference r, over all pixels and channels (N
/// values):
///   RMSE = √(Σ (x − r)² / N),  relMSE = Σ (x − r)² / (r² + ε) / N with ε = 10⁻²,
///   MAE = Σ |x − r| / N,  bias = Σ (x − r) / N with a 95% interval ± 1.96 s/√N (s the sample
///   standard deviation of x − r; pixels are independent, each has its own sample streams).
/// The z-test (as Mitsuba 3's test suite does it): with the standard errors σ_x, σ_r of each
/// value, z = (x − r)/√(σ_x² + σ_r²), p = 2(1 − Φ(|z|)) = erfc(|z|/√2), and the image passes at
/// level α when min p ≥ 1 − (1 − α)^{1/N} (Šidák). Values where both σ are 0 are left out.
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

}  // namespace shvol
