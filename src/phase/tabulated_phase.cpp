#include "shvol/phase/tabulated_phase.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace shvol {

TabulatedPhase::TabulatedPhase(const std::vector<double>& anglesDeg,
                               const std::vector<double>& values, std::string source) {
    const size_t n = anglesDeg.size();
    if (n < 2 || values.size() != n)
        throw std::invalid_argument("tabulated phase: need at least 2 (angle, value) rows");
    for (size_t i = 0; i < n; ++i)
        if (!(anglesDeg[i] >= 0 && anglesDeg[i] <= 180))
            throw std::invalid_argument("tabulated phase: angle outside [0, 180]");
    // Nodes in ascending μ: walk the table from 180° down to 0°.
    std::vector<double> mu, f;
    mu.reserve(n + 2), f.reserve(n + 2);
    if (anglesDeg.back() < 180) mu.push_back(-1.0), f.push_back(values.back());
    for (size_t k = n; k-- > 0;) {
        mu.push_back(anglesDeg[k] == 180 ? -1.0 : std::cos(anglesDeg[k] * (Pi / 180)));
        f.push_back(values[k]);
    }
    if (anglesDeg.front() > 0) mu.push_back(1.0), f.push_back(values.front());
    PiecewiseLinear1D table(std::move(mu), std::move(f));
    const double normalization = 1 / (TwoPi * table.integral());
    data_ = std::make_shared<const Data>(Data{std::move(table), normalization, std::move(source)});
}

double TabulatedPhase::evalCos(double cosTheta) const {
    return data_->table.eval(std::clamp(cosTheta, -1.0, 1.0)) * data_->normalization;
}

PhaseSample TabulatedPhase::sample(const Vec3& wo, const Vec2& u) const {
    const double cosTheta = data_->table.sample(u.x());
    const Vec3 wi = Frame(wo).toWorld(sphericalDirection2Pi(cosTheta, u.y()));
    const double p = evalCos(cosTheta);
    return {wi, p, p};
}

}  // namespace shvol
