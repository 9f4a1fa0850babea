#include "shvol/sampling/zonal_sh_sampler.h"

#include <algorithm>

#include "shvol/core/error.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_integrals.h"

namespace shvol {

namespace {
int checkedDepth(size_t order, int depth) {
    if (order < 1 || order > 1024) throw Error("ZonalSHSampler: order must be in [1, 1024]");
    if (depth < 1 || depth > 24) throw Error("ZonalSHSampler: depth must be in [1, 24]");
    return depth;
}
}  // namespace

ZonalSHSampler::ZonalSHSampler(std::vector<double> p, int depth)
    : p_(std::move(p)),
      depth_(checkedDepth(p_.size(), depth)),
      bins_(1 << depth_),
      binWidth_(2.0 / bins_) {
    const int n = int(p_.size());
    std::vector<double> Z(n), mass(bins_);
    int clamped = 0;
    for (int i = 0; i < bins_; ++i) {
        sh::legendreIntegralsZonal(n, -1 + i * binWidth_, -1 + (i + 1) * binWidth_, Z.data());
        double m = 0;
        for (int l = n - 1; l >= 0; --l) m += p_[l] * Z[l];
        m *= TwoPi;
        if (!(m > 0)) ++clamped, m = 0;
        mass[i] = m;
    }
    clampedFraction_ = double(clamped) / bins_;
    cdf_.resize(bins_ + 1);
    cdf_[0] = 0;
    for (int i = 0; i < bins_; ++i) cdf_[i + 1] = cdf_[i] + mass[i];
    total_ = cdf_[bins_];
    density_.assign(bins_, 0.0);
    if (!(total_ > 0)) return;
    for (int i = 0; i <= bins_; ++i) cdf_[i] /= total_;
    cdf_[bins_] = 1;
    for (int i = 0; i < bins_; ++i) density_[i] = mass[i] / (total_ * TwoPi * binWidth_);
    guide_.resize(bins_);
    for (int j = 0, i = 0; j < bins_; ++j) {
        const double t = double(j) / bins_;
        while (i < bins_ - 1 && cdf_[i + 1] <= t) ++i;
        guide_[j] = i;
    }
}

ZonalSHSampler::LocalSample ZonalSHSampler::warpLocal(const Vec2& u) const {
    if (!(total_ > 0)) return {};
    const double x = u.x();
    int i = guide_[std::min(bins_ - 1, int(x * bins_))];
    while (i < bins_ - 1 && cdf_[i + 1] <= x) ++i;
    // Position inside the bin: the rescaled remainder of u, as the hierarchical warp leaves it.
    const double width = cdf_[i + 1] - cdf_[i];
    // t < 1 so that z stays inside bin i, whose density is returned.
    const double t = width > 0 ? std::clamp((x - cdf_[i]) / width, 0.0, 1.0 - 0x1.0p-53) : 0.5;
    const double z = std::clamp(-1 + (i + t) * binWidth_, -1.0, 1.0);
    return {z, TwoPi * u.y(), density_[i]};
}

Vec3 ZonalSHSampler::warp(const Vec3& axis, const Vec2& u, double* pdf) const {
    const LocalSample s = warpLocal(u);
    *pdf = s.pdf;
    return Frame(axis).toWorld(sphericalDirection(s.cosTheta, s.phi));
}

SphereSample ZonalSHSampler::sample(const Vec3& axis, const Vec2& u) const {
    const LocalSample s = warpLocal(u);
    if (!(s.pdf > 0)) return {Vec3(0, 0, 1), 0, s.pdf};
    return {Frame(axis).toWorld(sphericalDirection(s.cosTheta, s.phi)), eval(s.cosTheta), s.pdf};
}

int ZonalSHSampler::bin(double z) const {
    return std::clamp(int((z + 1) / binWidth_), 0, bins_ - 1);
}

double ZonalSHSampler::pdf(double cosTheta) const {
    return total_ > 0 ? density_[bin(std::clamp(cosTheta, -1.0, 1.0))] : 0.0;
}

double ZonalSHSampler::cdf(double z) const {
    if (!(total_ > 0)) return 0;
    z = std::clamp(z, -1.0, 1.0);
    const int i = bin(z);
    const double t = std::clamp((z + 1) / binWidth_ - i, 0.0, 1.0);
    return cdf_[i] + t * (cdf_[i + 1] - cdf_[i]);
}

double ZonalSHSampler::eval(double cosTheta) const {
    double buffer[1024];  // order ≤ 1024 (checked in the constructor)
    double* y = buffer;
    sh::shEvalZonal(int(p_.size()), std::clamp(cosTheta, -1.0, 1.0), y);
    double v = 0;
    for (size_t l = 0; l < p_.size(); ++l) v += p_[l] * y[l];
    return v;
}

}  // namespace shvol
