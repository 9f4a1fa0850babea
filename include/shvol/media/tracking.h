#pragma once
/// \file Free-flight sampling and transmittance estimation against piecewise-constant majorants.
///
/// A ray crosses a sequence of segments [t0, t1) with majorant σ_maj ≥ σ_t(x). Within a segment
/// tentative collisions are drawn at rate σ_maj (t ← t − ln(1−u)/σ_maj); at each one the local
/// σ_t(x) is looked up.
///  - Delta tracking (Woodcock et al. 1965): the collision is real with probability σ_t/σ_maj;
///    the first real collision is distributed with density σ_t(t)·T(t).
///  - Ratio tracking (Cramer 1978; Novák et al. 2014, "Residual ratio tracking"): the unbiased
///    transmittance estimate T = Π (1 − σ_t/σ_maj) over all tentative collisions, with Russian
///    roulette once T is small so that optically thick media end the walk early.
/// Both are templates so the medium's lookup and segment walk are inlined (static dispatch).
#include <cmath>
#include <limits>

#include "shvol/core/rng.h"

namespace shvol {

/// Counters a medium adds to while tracking; summed over threads into the render statistics.
struct TrackingCounters {
    uint64_t densityLookups = 0;  ///< σ_t(x) evaluations (tentative collisions)
    uint64_t segments = 0;        ///< majorant segments visited
};

inline constexpr double NoCollision = std::numeric_limits<double>::infinity();

/// The walk both estimators share: tentative collisions at rate σ_maj within each segment.
/// `Segments` is a callable taking a visitor visit(t0, t1, sigmaMaj) → bool (false stops the walk);
/// at each tentative collision `collide(t, sigmaMaj)` is called and returns false to stop.
template <typename Segments, typename Collide>
void forEachTentativeCollision(const Segments& segments, Rng& rng, TrackingCounters& c,
                               Collide&& collide) {
    segments([&](double t0, double t1, double sigmaMaj) {
        ++c.segments;
        if (!(sigmaMaj > 0)) return true;
        for (double t = t0;;) {
            t -= std::log1p(-rng.uniform()) / sigmaMaj;
            if (t >= t1) return true;
            ++c.densityLookups;
            if (!collide(t, sigmaMaj)) return false;
        }
    });
}

/// Delta tracking: distance of the first real collision, or NoCollision. sigmaT(t) gives σ_t at
/// ray parameter t.
template <typename Segments, typename SigmaT>
double deltaTrack(const Segments& segments, const SigmaT& sigmaT, Rng& rng, TrackingCounters& c) {
    double hit = NoCollision;
    forEachTentativeCollision(segments, rng, c, [&](double t, double sigmaMaj) {
        if (rng.uniform() * sigmaMaj >= sigmaT(t)) return true;  // null collision
        hit = t;
        return false;
    });
    return hit;
}

/// Ratio-tracking estimate of T over all segments. Roulette below T = rrThreshold keeps the
/// estimator unbiased: survive with probability T/rrThreshold and continue with T = rrThreshold.
template <typename Segments, typename SigmaT>
double ratioTrack(const Segments& segments, const SigmaT& sigmaT, Rng& rng, TrackingCounters& c,
                  double rrThreshold = 0.1) {
    double T = 1;
    forEachTentativeCollision(segments, rng, c, [&](double t, double sigmaMaj) {
        T *= std::max(0.0, 1.0 - sigmaT(t) / sigmaMaj);
        if (T >= rrThreshold) return true;
        if (T <= 0 || rng.uniform() * rrThreshold >= T) {
            T = 0;
            return false;
        }
        T = rrThreshold;
        return true;
    });
    return T;
}

/// Binary transmittance estimate by delta tracking: 1 if no real collision before the end.
template <typename Segments, typename SigmaT>
double deltaTrackTransmittance(const Segments& segments, const SigmaT& sigmaT, Rng& rng,
                               TrackingCounters& c) {
    return deltaTrack(segments, sigmaT, rng, c) == NoCollision ? 1.0 : 0.0;
}

}  // namespace shvol
