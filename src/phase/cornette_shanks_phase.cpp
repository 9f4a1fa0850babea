#include "shvol/phase/cornette_shanks_phase.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "shvol/phase/henyey_greenstein.h"

namespace shvol {

double cornetteShanks(const AngleCosine& c, double g) {
    return henyeyGreenstein(c, g) * 1.5 * (1 + c.mu * c.mu) / (2 + g * g);
}

namespace {

/// Appends the nodes strictly inside (t0, t1) that make the linear interpolant of r(t) = 1 + μ(t)²
/// match r at every segment midpoint to kRefineTol (relative), bisecting recursively.
void refine(double t0, double r0, double t1, double r1, const HenyeyGreensteinSampler& hg,
            int depth, std::vector<std::pair<double, double>>* out) {
    constexpr double kRefineTol = 1e-5;
    const double tm = 0.5 * (t0 + t1);
    if (depth == 0 || !(tm > t0 && tm < t1)) return;
    const double mu = hg(tm).angle.mu;
    const double rm = 1 + mu * mu;
    if (std::abs(rm - 0.5 * (r0 + r1)) <= kRefineTol * rm) return;
    refine(t0, r0, tm, rm, hg, depth - 1, out);
    out->emplace_back(tm, rm);
    refine(tm, rm, t1, r1, hg, depth - 1, out);
}

}  // namespace

CornetteShanksPhase::CornetteShanksPhase(double g) : g_(g), hg_(g) {
    // Seed nodes uniform in t and uniform in μ (mapped to t), merged: the first resolve r where
    // the HG lobe is concentrated, the second where μ(t) moves fast (the tail, for |g| → 1).
    std::vector<std::pair<double, double>> seed;  // (t, r)
    seed.reserve(2 * kTableSize + 2);
    for (int j = 0; j <= kTableSize; ++j) {
        const double t = double(j) / kTableSize;
        seed.emplace_back(t, 1 + sqr(hg_(t).angle.mu));
        const double mu = -1 + 2.0 * j / kTableSize;
        seed.emplace_back(henyeyGreensteinCdf(mu, g), 1 + mu * mu);
    }
    std::sort(seed.begin(), seed.end());
    // Then bisect where the interpolant is still off (the constant c cancels in the
    // normalisation, so r = 1 + μ² is tabulated).
    std::vector<std::pair<double, double>> nodes;
    nodes.reserve(4 * seed.size());
    for (const auto& n : seed) {
        if (!nodes.empty() && !(n.first > nodes.back().first)) continue;  // duplicates
        if (!nodes.empty())
            refine(nodes.back().first, nodes.back().second, n.first, n.second, hg_, 12, &nodes);
        nodes.push_back(n);
    }
    std::vector<double> t, r;
    t.reserve(nodes.size()), r.reserve(nodes.size());
    for (const auto& [tj, rj] : nodes) t.push_back(tj), r.push_back(rj);
    warped_ = std::make_shared<const PiecewiseLinear1D>(std::move(t), std::move(r));
}

double CornetteShanksPhase::pdf(const Vec3& wo, const Vec3& wi) const {
    const AngleCosine c = AngleCosine::between(wo, wi);
    return warped_->pdf(henyeyGreensteinCdf(c, g_)) * henyeyGreenstein(c, g_);
}

PhaseSample CornetteShanksPhase::sample(const Vec3& wo, const Vec2& u) const {
    const double t = warped_->sample(u.x());
    const HenyeyGreensteinSampler::Sample s = hg_(t);
    const Vec3 wi = Frame(wo).toWorld(sphericalDirection2Pi(s.angle, u.y()));
    return {wi, cornetteShanks(s.angle, g_), warped_->pdf(t) * s.pdf};
}

}  // namespace shvol
