#include "shvol/phase/sh_sampled_phase.h"

#include <algorithm>
#include <cmath>

#include "shvol/core/error.h"
#include "shvol/phase/phase_function.h"
#include "shvol/sampling/warp.h"
#include "shvol/sampling/zonal_sh_sampler.h"
#include "shvol/sh/sh_projection.h"

namespace shvol {

namespace {
ZonalFitRequest explicitRequest(int order, SHWindow window) {
    if (order < 1) throw Error("SH order must be at least 1");
    ZonalFitRequest r;
    r.order = order;
    r.window = window;
    return r;
}
}  // namespace

SHSampledPhase::SHSampledPhase(const PhaseFunction& base, int order, SHWindow window,
                               Evaluate evaluate, int depth)
    : SHSampledPhase(base, explicitRequest(order, window), evaluate, depth) {}

SHSampledPhase::SHSampledPhase(const PhaseFunction& base, const ZonalFitRequest& request,
                               Evaluate evaluate, int depth)
    : base_(std::make_shared<const PhaseFunction>(base)), evaluate_(evaluate) {
    if (std::holds_alternative<SHSampledPhase>(base.variant()))
        throw Error("an SH-sampled phase function cannot wrap another one");
    const std::vector<double> corners = base_->corners();  // (a table's: one acos a row)
    fit_ = std::make_shared<const ZonalFit>(
        fitZonal([&](const AngleCosine& c) { return base_->evalAngle(c); }, request, corners));
    sampler_ = std::make_shared<const ZonalSHSampler>(fit_->p, depth);
    // (A function the fit's quadrature finds nothing of: a table's spike 10⁻⁵° wide at 90° was
    // one until the nodes ended at a table's corners, and its message said only that there was
    // no mass, not why or what to do; helper 103. No table is one now: a guard.)
    if (!(sampler_->positiveMass() > 0))
        throw Error(
            "the SH fit has no positive mass: the phase function is 0 wherever the fit's "
            "quadrature looks (structure narrower than its nodes, such as a spike of a table); "
            "sample it with \"sampling\": \"analytic\"");
    if (evaluate_ == Evaluate::Exact && sampler_->clampedFraction() > 0)
        alpha_ = kDefensiveFraction;
    checkByQuadrature(corners);
}

double SHSampledPhase::baseCos(double mu) const {
    return base_->evalAngle(AngleCosine::of(mu));
}

template <typename Node>
void SHSampledPhase::forEachNode(const std::vector<double>& corners, Node&& node) const {
    const int bins = 1 << sampler_->depth();
    std::vector<double> edges = gradedThetaEdges(corners);
    edges.reserve(edges.size() + bins);
    for (int i = 1; i < bins; ++i) edges.push_back(std::acos(1 - 2.0 * i / bins));
    std::sort(edges.begin(), edges.end());
    std::vector<double> x, w;  // 4-point rule on [0, 1], mapped to each interval
    sh::gaussLegendre(4, 0.0, 1.0, x, w);
    for (size_t i = 0; i + 1 < edges.size(); ++i) {
        const double a = edges[i], h = edges[i + 1] - edges[i];
        if (!(h > 0)) continue;
        const double pdf = pdfCos(std::cos(a + 0.5 * h));
        for (size_t j = 0; j < x.size(); ++j) {
            const double t = a + h * x[j];
            node(base_->evalAngle(AngleCosine::ofAngle(t)), pdf, TwoPi * h * w[j] * std::sin(t));
        }
    }
}

void SHSampledPhase::checkByQuadrature(const std::vector<double>& corners) {
    // One pass over the nodes: ∫p (quadratureMass), and m₂ (Exact) or the rendered error.
    double m2 = 0, error = 0, energy = 0;
    bool unsampled = false;  // p > 0 where pdf = 0
    forEachNode(corners, [&](double p, double pdf, double w) {
        quadratureMass_ += w * p;
        if (evaluate_ == Evaluate::Exact) {
            if (p > 0 && !(pdf > 0)) unsampled = true;
            if (p > 0 && pdf > 0) m2 += w * p * p / pdf;
        } else {
            // (Reconstruction: eval = pdf, constant on the interval; α = 0.)
            error += w * (pdf - p) * (pdf - p);
            energy += w * p * p;
        }
    });
    if (evaluate_ == Evaluate::Exact)
        m2_ = unsampled ? INFINITY : m2;
    else
        renderedError_ = energy > 0 ? std::sqrt(error / energy) : 0.0;
}

double SHSampledPhase::evalCos(double mu) const {
    return evaluate_ == Evaluate::Exact ? baseCos(mu) : sampler_->pdf(mu);
}

double SHSampledPhase::pdfCos(double mu) const {
    return (1 - alpha_) * sampler_->pdf(mu) + alpha_ * Inv4Pi;
}

double SHSampledPhase::eval(const Vec3& wo, const Vec3& wi) const {
    return evaluate_ == Evaluate::Exact ? base_->eval(wo, wi) : evalCos(wo.dot(wi));
}

double SHSampledPhase::pdf(const Vec3& wo, const Vec3& wi) const {
    return pdfCos(wo.dot(wi));
}

PhaseSample SHSampledPhase::sample(const Vec3& wo, const Vec2& u) const {
    Vec3 wi;
    if (u.x() < alpha_) {
        wi = sampleUniformSphere(Vec2(u.x() / alpha_, u.y()));
    } else {
        double pdfSH;
        wi = sampler_->warp(wo, Vec2((u.x() - alpha_) / (1 - alpha_), u.y()), &pdfSH);
    }
    const double p = pdf(wo, wi);
    return {wi, p > 0 ? eval(wo, wi) : 0.0, p};
}

}  // namespace shvol
