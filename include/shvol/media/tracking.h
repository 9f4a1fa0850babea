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
#include <algorithm>
#include <cmath>
#include <limits>

#include "shvol/core/rng.h"
#include "shvol/sampling/russian_roulette.h"

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
/// σ_min = 0 both functions are plain delta and ratio tracking.
///
/// Both Poisson processes (control events at rate σ_min, tentative collisions at rate
/// σ_maj − σ_min) have piecewise-constant rates, so each is sampled by inverting its cumulative
/// rate Λ(t) = ∫ rate: the next event after s is where Λ grows by E ~ Exp(1). The unused part of
/// E is carried into the next segment (the optical-depth budget below) instead of drawing a new
/// exponential per segment, which the memorylessness of the exponential would also allow: a
/// segment without an event costs a multiply and a compare, no logarithm and no random number,
/// and splitting a segment in two does not change the numbers drawn.

/// The uniform numbers of one free flight: the first two from a pair drawn from the path's
/// sample stream (a Sobol' request, stratified over a pixel's samples), the rest from an Rng.
/// Without a pair every number comes from the Rng.
class FlightNumbers {
  public:
    FlightNumbers(const Rng& rng, const Vec2* first) : rng_(rng), left_(first ? 2 : 0) {
        if (first) first_[0] = first->x(), first_[1] = first->y();
    }
    double uniform() { return left_ > 0 ? first_[2 - left_--] : rng_.uniform(); }
    const Rng& rng() const { return rng_; }

  private:
    Rng rng_;
    int left_;
    double first_[2] = {0, 0};
};

/// An optical-depth budget E ~ Exp(1) of a Poisson process with piecewise-constant rate: drawn
/// when first needed, spent segment by segment.
class OpticalDepthBudget {
  public:
    /// Moves *t, at rate `rate` > 0 (invRate = 1/rate), to the process's next event if it comes
    /// before tEnd (true; the next call draws a new budget), else spends the budget up to tEnd
    /// (false, *t unchanged). The budget carried from segment to segment only has the segment's
    /// optical depth subtracted (one subtraction on the chain from one segment to the next; the
    /// optical depth itself depends only on the segment).
    template <typename Uniform>
    bool next(double rate, double invRate, double tEnd, Uniform& rng, double* t) {
        if (tau_ < 0) tau_ = exponentialVariate(rng.uniform());
        const double depth = (tEnd - *t) * rate, tEvent = *t + tau_ * invRate;
        if (tau_ >= depth || tEvent >= tEnd) {  // (the second: an event rounded onto tEnd)
            tau_ = std::max(0.0, tau_ - depth);
            return false;
        }
        *t = tEvent;
        tau_ = -1;
        return true;
    }

  private:
    double tau_ = -1;  ///< the budget left, or < 0: not drawn
};

namespace detail {
/// The walk along the segments of delta tracking (kDelta: the first real collision, returned,
/// or NoCollision) or residual ratio tracking (kRatio: the transmittance estimate to the end of
/// the segments, in *transmittance). Both at once would serve both from the same tentative
/// collisions (next-flight estimation, Novák et al. 2014 §5); measured under a constant sky it
/// raised the error (validation/cycles/README.md), so nothing asks for it.
template <bool kDelta, bool kRatio, typename Segments, typename SigmaT>
double track(const Segments& segments, const SigmaT& sigmaT, Rng& rngRef,
             TrackingCounters& counters, const Vec2* first, double* transmittance,
             double rrThreshold) {
    // The walk works on local copies (kept in registers: the caller's objects could alias the
    // lookups' memory as far as the compiler knows) and writes them back at the end.
    FlightNumbers rng(rngRef, first);
    TrackingCounters c = counters;
    double hit = kDelta ? NoCollision : 0, T = kRatio ? 1 : 0;
    // Ratio tracking's roulette once T is below the threshold: the path's survival-weight rule
    // (rouletteSurvival) with its own threshold: survive with probability T/rrThreshold and
    // continue with T = rrThreshold, else T = 0.
    auto roulette = [&] {
        if (T >= rrThreshold) return;
        T = rng.uniform() < rouletteSurvival(T, rrThreshold) ? rrThreshold : 0;
    };
    auto tracking = [&] { return kDelta && hit == NoCollision; };
    auto ratio = [&] { return kRatio && T > 0; };
    OpticalDepthBudget control, residual;
    segments([&](double t0, double t1, double sigmaMaj, double sigmaMin) {
        ++c.segments;
        if (!(sigmaMaj > 0)) return true;
        // The control part: delta tracking's exponential event at rate σ_min (a real collision),
        // ratio tracking's factor e^{−σ_min (t1 − t0)}.
        double tControl = t0;
        if (!(tracking() && sigmaMin > 0 &&
              control.next(sigmaMin, 1 / sigmaMin, t1, rng, &tControl)))
            tControl = t1;
        if (ratio() && sigmaMin > 0) {
            T *= std::exp(-sigmaMin * (t1 - t0));
            roulette();
        }
        // The residual part: tentative collisions at rate σ_maj − σ_min, up to where either
        // estimator still needs them.
        const double sigmaRes = sigmaMaj - sigmaMin, invRes = 1 / sigmaRes;
        double tEnd = ratio() ? t1 : tracking() ? tControl : t0;
        if (sigmaRes > 0)
            for (double t = t0; t < tEnd && residual.next(sigmaRes, invRes, tEnd, rng, &t);) {
                ++c.densityLookups;
                const double s = sigmaT(t) - sigmaMin;
                if (tracking() && rng.uniform() * sigmaRes < s) {  // a real collision
                    hit = t;
                    if (!ratio()) break;
                }
                if (ratio()) {
                    T *= std::max(0.0, 1.0 - s * invRes);
                    roulette();
                    if (!ratio()) tEnd = tracking() ? tControl : t0;
                }
            }
        if (tracking() && tControl < t1) hit = tControl;
        return tracking() || ratio();
    });
    rngRef = rng.rng(), counters = c;
    if (kRatio) *transmittance = T;
    return hit;
}
}  // namespace detail

/// Delta tracking with decomposition (Kutz et al. 2017, "Spectral and Decomposition Tracking
/// for Rendering Heterogeneous Volumes", §4): the first real collision is the earlier of the
/// control part's (exponential with rate σ_min) and the residual part's (delta tracking with
/// majorant σ_maj − σ_min); the two are independent Poisson processes whose sum has rate σ_t.
/// Returns its distance, or NoCollision. sigmaT(t) gives σ_t at ray parameter t. The first two
/// numbers come from `first` when given (FlightNumbers), the others from rng.
template <typename Segments, typename SigmaT>
double deltaTrack(const Segments& segments, const SigmaT& sigmaT, Rng& rng, TrackingCounters& c,
                  const Vec2* first = nullptr) {
    return detail::track<true, false>(segments, sigmaT, rng, c, first, nullptr, 0.0);
}

/// Residual ratio tracking (Novák, Selle & Jarosz 2014, "Residual Ratio Tracking for
/// Estimating Attenuation in Participating Media", §4), with the control part per segment:
/// T = Π_segments e^{−σ_min (t1 − t0)} Π_points (1 − (σ_t − σ_min)/(σ_maj − σ_min)), over
/// tentative points at rate σ_maj − σ_min. Roulette below T = rrThreshold keeps it unbiased:
/// survive with probability T/rrThreshold and continue with T = rrThreshold.
template <typename Segments, typename SigmaT>
double ratioTrack(const Segments& segments, const SigmaT& sigmaT, Rng& rng, TrackingCounters& c,
                  double rrThreshold = 0.1) {
    double T;
    detail::track<false, true>(segments, sigmaT, rng, c, nullptr, &T, rrThreshold);
    return T;
}

/// Binary transmittance estimate by delta tracking: 1 if no real collision before the end.
template <typename Segments, typename SigmaT>
double deltaTrackTransmittance(const Segments& segments, const SigmaT& sigmaT, Rng& rng,
                               TrackingCounters& c) {
    return deltaTrack(segments, sigmaT, rng, c) == NoCollision ? 1.0 : 0.0;
}

}  // namespace shvol
