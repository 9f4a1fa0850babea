#include "shvol/sampling/distribution_1d.h"

#include <algorithm>
#include <cmath>

#include "shvol/core/error.h"
#include "shvol/core/math.h"

namespace shvol {

Distribution1D::Distribution1D(const double* f, int n) {
    if (n <= 0) fail("", "Distribution1D", "needs at least one bin");
    func_.resize(n);
    for (int i = 0; i < n; ++i) func_[i] = (f[i] > 0 && std::isfinite(f[i])) ? f[i] : 0.0;
    cdf_.resize(n + 1);
    cdf_[0] = 0;
    for (int i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + func_[i];
    const double sum = cdf_[n];
    integral_ = sum / n;
    allZero_ = !(sum > 0);
    if (allZero_) {
        for (int i = 0; i <= n; ++i) cdf_[i] = double(i) / n;
    } else {
        for (int i = 1; i < n; ++i) cdf_[i] /= sum;
    }
    cdf_[n] = 1.0;
    guide_.resize(n + 1);
    for (int k = 0; k <= n; ++k) guide_[k] = lastAtMost(0, n + 1, double(k) / n);
}

int Distribution1D::lastAtMost(int first, int last, double u) const {
    return int(std::upper_bound(cdf_.begin() + first, cdf_.begin() + last, u) - cdf_.begin()) - 1;
}

int Distribution1D::validBin(int i) const {
    const int n = count();
    // Because cdf is non-decreasing, cdf[i+1] > u for the last i with cdf[i] ≤ u whenever u < 1,
    // so that bin has positive width (non-zero weight).
    i = std::clamp(i, 0, n - 1);
    // Only reachable through rounding (u ≥ cdf[n]): step back to a bin with weight.
    while (i > 0 && cdf_[i + 1] <= cdf_[i]) --i;
    while (i < n - 1 && cdf_[i + 1] <= cdf_[i]) ++i;
    return i;
}

int Distribution1D::findBin(double u) const {
    const int n = count();
    u = clampToUnit(u);  // (NaN too: int(u·n) below must stay defined)
    // The guide cell k with k/n ≤ u < (k+1)/n, the quotients computed as the table's were (the
    // product u·n may round across a cell boundary).
    int k = std::clamp(int(u * n), 0, n - 1);
    while (k > 0 && double(k) / n > u) --k;
    while (k + 1 < n && double(k + 1) / n <= u) ++k;
    // The last i with cdf[i] ≤ u lies in [g_k, g_{k+1}]: search cdf[g_k + 1 … g_{k+1}].
    return validBin(lastAtMost(guide_[k] + 1, guide_[k + 1] + 1, u));
}

int Distribution1D::findBinBySearch(double u) const {
    return validBin(lastAtMost(0, count() + 1, u));
}

double Distribution1D::sampleContinuous(double u, double* pdf, int* offset) const {
    const int n = count();
    u = clampToUnit(u);  // (NaN too: it would make x NaN and the loops below endless)
    const int i = findBin(u);
    if (offset) *offset = i;
    if (pdf) *pdf = allZero_ ? 1.0 : func_[i] / integral_;
    const double width = cdf_[i + 1] - cdf_[i];
    double du = width > 0 ? (u - cdf_[i]) / width : 0.0;
    return pointInBin(i, std::clamp(du, 0.0, 1.0), n);
}

double pointInBin(int i, double du, int n) {
    double x = (i + du) / n;
    while (x > 0 && std::min(int(x * n), n - 1) > i) x = std::nextafter(x, 0.0);
    while (std::min(int(x * n), n - 1) < i) x = std::nextafter(x, 1.0);
    return std::min(x, std::nextafter(1.0, 0.0));
}

int Distribution1D::sampleDiscrete(double u, double* pmf) const {
    u = clampToUnit(u);
    const int i = findBin(u);
    if (pmf) *pmf = cdf_[i + 1] - cdf_[i];
    return i;
}

double Distribution1D::pdf(double x) const {
    const int n = count();
    const int i = std::clamp(int(x * n), 0, n - 1);
    return allZero_ ? 1.0 : func_[i] / integral_;
}

double Distribution1D::pmf(int i) const {
    return cdf_[i + 1] - cdf_[i];
}

}  // namespace shvol
