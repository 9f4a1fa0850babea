#include "shvol/phase/sh_sampled_phase.h"

#include "shvol/core/error.h"
#include "shvol/phase/phase_function.h"
#include "shvol/sampling/warp.h"
#include "shvol/sampling/zonal_sh_sampler.h"

namespace shvol {

SHSampledPhase::SHSampledPhase(const PhaseFunction& base, int order, SHWindow window,
                               Evaluate evaluate, int depth)
    : base_(std::make_shared<const PhaseFunction>(base)), evaluate_(evaluate) {
    if (std::holds_alternative<SHSampledPhase>(base.variant()))
        throw Error("an SH-sampled phase function cannot wrap another one");
    const Vec3 z(0, 0, 1);
    fit_ = std::make_shared<const ZonalFit>(fitZonal(
        [&](double mu) { return base_->eval(z, sphericalDirection(mu, 0)); }, order, window));
    sampler_ = std::make_shared<const ZonalSHSampler>(fit_->p, depth);
    if (!(sampler_->positiveMass() > 0)) throw Error("the SH fit has no positive mass");
    if (evaluate_ == Evaluate::Exact && sampler_->clampedFraction() > 0)
        alpha_ = kDefensiveFraction;
}

double SHSampledPhase::evalCos(double mu) const {
    if (evaluate_ == Evaluate::Exact) return base_->eval(Vec3(0, 0, 1), sphericalDirection(mu, 0));
    return sampler_->pdf(mu);
}

double SHSampledPhase::eval(const Vec3& wo, const Vec3& wi) const {
    return evaluate_ == Evaluate::Exact ? base_->eval(wo, wi) : evalCos(wo.dot(wi));
}

double SHSampledPhase::pdf(const Vec3& wo, const Vec3& wi) const {
    return (1 - alpha_) * sampler_->pdf(wo.dot(wi)) + alpha_ * Inv4Pi;
}

PhaseSample SHSampledPhase::sample(const Vec3& wo, const Vec2& u) const {
    Vec3 wi;
    if (u.x() < alpha_) {
        wi = sampleUniformSphere(Vec2(u.x() / alpha_, u.y()));
    } else {
        double pdfSH;
        wi = sampler_->sample(wo, Vec2((u.x() - alpha_) / (1 - alpha_), u.y()), &pdfSH);
    }
    const double p = pdf(wo, wi);
    return {wi, p > 0 ? eval(wo, wi) : 0.0, p};
}

}  // namespace shvol
