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

/// Free-flight sampling and transmittance estimation in a medium described by segments.
/// `Segments` is a callable taking a visitor visit(t0, t1, σ_maj, σ_min) → bool (false stops the
/// walk) with σ_min ≤ σ_t(t) ≤ σ_maj on [t0, t1). σ_t splits into a control part σ_min, constant
/// on the segment and handled in closed form without any density lookup, and a residual part
/// σ_t − σ_min ∈ [0, σ_maj − σ_min], tracked with null collisions at rate σ_maj − σ_min. With
/// σ_min = 0 both functions are plain delta and ratio tracking and draw the same numbers.

/// Delta tracking with decomposition (Kutz et al. 2017, "Spectral and Decomposition Tracking
/// for Rendering Heterogeneous Volumes", §4): the first real collision is the earlier of the
/// control part's (exponential with rate σ_min) and the residual part's (delta tracking with
/// majorant σ_maj − σ_min); the two are independent Poisson processes whose sum has rate σ_t.
/// Returns its distance, or NoCollision. sigmaT(t) gives σ_t at ray parameter t.
template <typename Segments, typename SigmaT>
double deltaTrack(const Segments& segments, const SigmaT& sigmaT, Rng& rng, TrackingCounters& c) {
    double hit = NoCollision;
    segments([&](double t0, double t1, double sigmaMaj, double sigmaMin) {
        ++c.segments;
        if (!(sigmaMaj > 0)) return true;
        double tControl = t1;
        if (sigmaMin > 0) tControl = std::min(t1, t0 - std::log1p(-rng.uniform()) / sigmaMin);
        const double sigmaRes = sigmaMaj - sigmaMin;
        if (sigmaRes > 0)
            for (double t = t0;;) {
                t -= std::log1p(-rng.uniform()) / sigmaRes;
                if (t >= tControl) break;
                ++c.densityLookups;
                if (rng.uniform() * sigmaRes < sigmaT(t) - sigmaMin) {  // a real collision
                    hit = t;
                    return false;
                }
            }
        if (tControl >= t1) return true;
        hit = tControl;
        return false;
    });
    return hit;
}

/// Residual ratio tracking (Novák, Selle & Jarosz 2014, "Residual Ratio Tracking for
/// Estimating Attenuation in Participating Media", §4), with the control part per segment:
/// T = Π_segments e^{−σ_min (t1 − t0)} Π_points (1 − (σ_t − σ_min)/(σ_maj − σ_min)), over
/// tentative points at rate σ_maj − σ_min. Roulette below T = rrThreshold keeps it unbiased:
/// survive with probability T/rrThreshold and continue with T = rrThreshold.
template <typename Segments, typename SigmaT>
double ratioTrack(const Segments& segments, const SigmaT& sigmaT, Rng& rng, TrackingCounters& c,
                  double rrThreshold = 0.1) {
    double T = 1;
    // After each factor: roulette once T is below the threshold; false ends the walk (T = 0).
    auto roulette = [&] {
        if (T >= rrThreshold) return true;
        if (T <= 0 || rng.uniform() * rrThreshold >= T) {
            T = 0;
            return false;
        }
        T = rrThreshold;
        return true;
    };
    segments([&](double t0, double t1, double sigmaMaj, double sigmaMin) {
        ++c.segments;
        if (!(sigmaMaj > 0)) return true;
        if (sigmaMin > 0) {
            T *= std::exp(-sigmaMin * (t1 - t0));
            if (!roulette()) return false;
        }
        const double sigmaRes = sigmaMaj - sigmaMin;
        if (!(sigmaRes > 0)) return true;
        for (double t = t0;;) {
            t -= std::log1p(-rng.uniform()) / sigmaRes;
            if (t >= t1) return true;
            ++c.densityLookups;
            T *= std::max(0.0, 1.0 - (sigmaT(t) - sigmaMin) / sigmaRes);
            if (!roulette()) return false;
        }
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
