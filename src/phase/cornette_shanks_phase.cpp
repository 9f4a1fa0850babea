#include "shvol/phase/cornette_shanks_phase.h"

#include <vector>

#include "shvol/phase/henyey_greenstein.h"

namespace shvol {

double cornetteShanks(double cosTheta, double g) {
    const double mu = std::clamp(cosTheta, -1.0, 1.0);
    return henyeyGreenstein(mu, g) * 1.5 * (1 + mu * mu) / (2 + g * g);
}

CornetteShanksPhase::CornetteShanksPhase(double g) : g_(g) {
    std::vector<double> t(kTableSize + 1), r(kTableSize + 1);
    for (int j = 0; j <= kTableSize; ++j) {
        t[j] = double(j) / kTableSize;
        const double mu = sampleHenyeyGreensteinCosTheta(t[j], g);
        r[j] = 1 + mu * mu;  // the constant c cancels in the normalisation
    }
    warped_ = std::make_shared<const PiecewiseLinear1D>(std::move(t), std::move(r));
}

double CornetteShanksPhase::pdf(const Vec3& wo, const Vec3& wi) const {
    const double mu = std::clamp(wo.dot(wi), -1.0, 1.0);
    return warped_->pdf(henyeyGreensteinCdf(mu, g_)) * henyeyGreenstein(mu, g_);
}

PhaseSample CornetteShanksPhase::sample(const Vec3& wo, const Vec2& u) const {
    const double t = warped_->sample(u.x());
    const double cosTheta = sampleHenyeyGreensteinCosTheta(t, g_);
    const Vec3 wi = Frame(wo).toWorld(sphericalDirection(cosTheta, TwoPi * u.y()));
    return {wi, cornetteShanks(cosTheta, g_), warped_->pdf(t) * henyeyGreenstein(cosTheta, g_)};
}

}  // namespace shvol
