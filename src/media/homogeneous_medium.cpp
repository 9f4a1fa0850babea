#include "shvol/media/homogeneous_medium.h"

namespace shvol {

Interval MediumShape::intersect(const Ray& ray, double tMax) const {
    switch (type) {
        case Type::Box:
            return intersectBox(ray, lo, hi, tMax);
        case Type::Sphere:
            return intersectSphere(ray, center, radius, tMax);
        default:
            return Interval{0, tMax};
    }
}

Bounds3 HomogeneousMedium::bounds() const {
    switch (shape_.type) {
        case MediumShape::Type::Box:
            return {shape_.lo, shape_.hi};
        case MediumShape::Type::Sphere: {
            // Widened by a rounding margin, as center ± radius may round inwards.
            const Vec3 r =
                Vec3::Constant(shape_.radius * (1 + 1e-12)) + 1e-12 * shape_.center.cwiseAbs();
            return {shape_.center - r, shape_.center + r};
        }
        default:
            return {};
    }
}

bool MediumShape::contains(const Vec3& p) const {
    if (type == Type::Everywhere) return true;
    if (type == Type::Box)
        return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
    return (p - center).squaredNorm() <= radius * radius;
}

HomogeneousMedium::HomogeneousMedium(MediumShape shape, double sigmaT, Spectrum albedo,
                                     PhaseFunction phase, bool tracking)
    : Medium(albedo, std::move(phase)), shape_(shape), sigmaT_(sigmaT), tracking_(tracking) {}

double HomogeneousMedium::sampleCollision(const Ray& ray, double tMax, Rng& rng,
                                          TrackingCounters& c, const Vec2* first) const {
    const Interval iv = shape_.intersect(ray, tMax);
    if (iv.empty() || !(sigmaT_ > 0)) return NoCollision;
    if (tracking_) {
        auto segments = [&](auto&& visit) { visit(iv.t0, iv.t1, 2 * sigmaT_, 0.0); };
        return deltaTrack(
            segments, [&](double) { return sigmaT_; }, rng, c, first);
    }
    ++c.segments;
    const double t = iv.t0 + exponentialVariate(first ? first->x() : rng.uniform()) / sigmaT_;
    return t < iv.t1 ? t : NoCollision;
}

double HomogeneousMedium::transmittance(const Ray& ray, double tMax, TransmittanceEstimator est,
                                        Rng& rng, TrackingCounters& c) const {
    const Interval iv = shape_.intersect(ray, tMax);
    if (iv.empty() || !(sigmaT_ > 0)) return 1;
    if (!tracking_ && est == TransmittanceEstimator::Ratio) {
        ++c.segments;
        return std::exp(-sigmaT_ * (iv.t1 - iv.t0));
    }
    auto segments = [&](auto&& visit) { visit(iv.t0, iv.t1, (tracking_ ? 2 : 1) * sigmaT_, 0.0); };
    auto sigma = [&](double) { return sigmaT_; };
    return est == TransmittanceEstimator::Ratio ? ratioTrack(segments, sigma, rng, c)
                                                : deltaTrackTransmittance(segments, sigma, rng, c);
}

std::string HomogeneousMedium::describe() const {
    switch (shape_.type) {
        case MediumShape::Type::Box:
            return "homogeneous box";
        case MediumShape::Type::Sphere:
            return "homogeneous sphere";
        default:
            return "homogeneous (inside its boundary)";
    }
}

}  // namespace shvol
