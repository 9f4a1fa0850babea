#include "shvol/phase/piecewise_linear_1d.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace shvol {

PiecewiseLinear1D::PiecewiseLinear1D(std::vector<double> x, std::vector<double> f)
    : x_(std::move(x)), f_(std::move(f)) {
    const size_t n = x_.size();
    if (n < 2 || f_.size() != n)
        throw std::invalid_argument("PiecewiseLinear1D: need ≥ 2 nodes and one value per node");
    for (size_t i = 0; i < n; ++i) {
        if (!std::isfinite(x_[i]) || !std::isfinite(f_[i]) || f_[i] < 0)
            throw std::invalid_argument("PiecewiseLinear1D: non-finite node or negative value");
        if (i > 0 && !(x_[i] > x_[i - 1]))
            throw std::invalid_argument("PiecewiseLinear1D: nodes must increase strictly");
    }
    cdf_.assign(n, 0.0);
    for (size_t i = 0; i + 1 < n; ++i)
        cdf_[i + 1] = cdf_[i] + 0.5 * (x_[i + 1] - x_[i]) * (f_[i] + f_[i + 1]);
    integral_ = cdf_.back();
    if (!(integral_ > 0) || !std::isfinite(integral_))
        throw std::invalid_argument("PiecewiseLinear1D: integral is zero or not finite");
    for (double& c : cdf_) c /= integral_;
    cdf_.back() = 1.0;
}

int PiecewiseLinear1D::segment(double x) const {
    const auto it = std::upper_bound(x_.begin(), x_.end(), x);
    return std::clamp(int(it - x_.begin()) - 1, 0, int(x_.size()) - 2);
}

double PiecewiseLinear1D::eval(double x) const {
    if (!(x >= x_.front() && x <= x_.back())) return 0.0;  // also NaN
    const int i = segment(x);
    const double s = std::clamp((x - x_[i]) / (x_[i + 1] - x_[i]), 0.0, 1.0);
    return (1 - s) * f_[i] + s * f_[i + 1];
}

double PiecewiseLinear1D::cdf(double x) const {
    if (!(x > x_.front())) return 0.0;
    if (x >= x_.back()) return 1.0;
    const int i = segment(x);
    const double h = x_[i + 1] - x_[i];
    const double s = std::clamp((x - x_[i]) / h, 0.0, 1.0);
    // ∫₀ˢ ((1 − t) fᵢ + t fᵢ₊₁) h dt = h s (fᵢ + s (fᵢ₊₁ − fᵢ)/2) = h s ((1 − s/2) fᵢ + (s/2) fᵢ₊₁)
    const double part = h * s * ((1 - 0.5 * s) * f_[i] + 0.5 * s * f_[i + 1]);
    return std::min(1.0, cdf_[i] + part / integral_);
}

double PiecewiseLinear1D::sample(double u) const {
    // u = 0 or 1 exactly would map to the end of the support, where f may be 0 (a table that
    // starts or ends with zeros) and the sample would have value and pdf 0; 2^−53 from either
    // end the sample is inside a segment with mass. (Moves at most 2^−53 of probability.)
    u = std::clamp(u, 0x1p-53, 1 - 0x1p-53);
    // Last i with cdf_[i] ≤ u, so segment i has non-zero mass unless u = 1.
    int i = int(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin()) - 1;
    i = std::clamp(i, 0, int(x_.size()) - 2);
    while (i > 0 && cdf_[i + 1] == cdf_[i]) --i;  // u = 1 landed on trailing empty segments
    const double mass = cdf_[i + 1] - cdf_[i];
    // Kept 2^−53 inside the segment too: u exactly on a cdf node would otherwise land on the node,
    // where f may be 0 between two lobes (a table 1, 0, 1 sampled at u = ½).
    const double v = mass > 0 ? std::clamp((u - cdf_[i]) / mass, 0x1p-53, 1 - 0x1p-53) : 0.0;
    const double f0 = f_[i], f1 = f_[i + 1];
    const double num = v * (f0 + f1);
    const double den = f0 + std::sqrt((1 - v) * f0 * f0 + v * f1 * f1);
    const double s = den > 0 ? std::clamp(num / den, 0.0, 1.0) : 0.0;
    const double x = std::clamp(x_[i] + s * (x_[i + 1] - x_[i]), x_[i], x_[i + 1]);
    // A segment a few doubles wide (a lobe of 10⁻⁶° in cos θ is one) holds no point but its ends:
    // x rounds onto the end where f may be 0, and the sample had value and pdf 0 (a quarter of
    // them for the 10⁻⁶° lobe, a furnace rendered 0.007; helper 76). The nearest double inside
    // the segment has f̃ > 0. (Moves a sample by one double.)
    if (eval(x) == 0 && f0 + f1 > 0) return std::nextafter(x, f0 > 0 ? x_[i] : x_[i + 1]);
    return x;
}

}  // namespace shvol
