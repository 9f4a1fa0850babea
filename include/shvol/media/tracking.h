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
/// Both are templates so the medium's lookup and segment walk are inlined (static dispatch), and
/// forced inline with the budget's step: once regular tracking (TrilinearDepth) made them larger
/// than clang's threshold, they became calls, and the lookup a call in their loop (dense cloud
/// of validation/cycles, perf: 32% of the time in sampleCollision before, 39% in three
/// functions after).
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "shvol/core/rng.h"
#include "shvol/sampling/russian_roulette.h"

namespace shvol {

/// Counters a medium adds to while tracking; summed over threads into the render statistics.
struct TrackingCounters {
    uint64_t densityLookups = 0;  ///< σ_t(x) evaluations (tentative collisions)
    uint64_t segments = 0;        ///< majorant segments visited
    uint64_t exactCells = 0;      ///< voxel cells crossed by regular tracking (TrilinearDepth)
};

/// No regular tracking: the default of deltaTrack and ratioTrack, which then take every segment
/// by tentative collisions. A medium that can integrate its density exactly along a ray passes
/// an object with preferred(t0, t1, lookupRate) → bool, spend(t0, t1, &e, &t, counters) → bool
/// and depth(t0, t1, counters, stop) → τ instead (TrilinearDepth); the trackers then take the
/// segments it prefers in closed form.
struct NoRegularTracking {};

inline constexpr double NoCollision = std::numeric_limits<double>::infinity();

/// Free-flight sampling and transmittance estimation in a medium described by segments.
/// `Segments` is a callable taking a visitor visit(t0, t1, σ_maj, σ_min) → bool (false stops the
/// walk) with σ_min ≤ σ_t(t) ≤ σ_maj on [t0, t1). σ_min, constant on the segment, is known without
/// any density lookup, and both functions use it to look σ_t up less often: ratio tracking takes
/// the control part σ_min in closed form and tracks the residual σ_t − σ_min ∈ [0, σ_maj − σ_min]
/// with tentative collisions at rate σ_maj − σ_min; delta tracking decides the tentative
/// collisions (rate σ_maj) whose acceptance number falls below σ_min/σ_maj without a lookup. With
/// σ_min = 0 both are plain delta and ratio tracking.
///
/// Tentative collisions come from a Poisson process with a piecewise-constant rate, sampled by
/// inverting its cumulative rate Λ(t) = ∫ rate: the next event after s is where Λ grows by
/// E ~ Exp(1). The unused part of E is carried into the next segment (the optical-depth budget
/// below) instead of drawing a new exponential per segment, which the memorylessness of the
/// exponential would also allow: a segment without an event costs a multiply and a compare, no
/// logarithm and no random number, and splitting a segment in two does not change the numbers
/// drawn.

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
    __attribute__((always_inline)) bool next(double rate, double invRate, double tEnd, Uniform& rng,
                                             double* t) {
        left(rng);
        const double depth = (tEnd - *t) * rate, tEvent = *t + tau_ * invRate;
        if (tau_ >= depth || tEvent >= tEnd) {  // (the second: an event rounded onto tEnd)
            tau_ = std::max(0.0, tau_ - depth);
            return false;
        }
        *t = tEvent;
        tau_ = -1;
        return true;
    }
    /// The budget left, drawn first if it is not: for a segment whose optical depth is spent
    /// exactly (regular tracking) rather than by events at a constant rate.
    template <typename Uniform>
    double* left(Uniform& rng) {
        if (tau_ < 0) tau_ = exponentialVariate(rng.uniform());
        return &tau_;
    }

  private:
    double tau_ = -1;  ///< the budget left, or < 0: not drawn
};

/// Delta tracking (Woodcock et al. 1965) against σ_maj per segment, with σ_min ≤ σ_t sparing
/// lookups: the tentative collision at t (rate σ_maj) is real iff u·σ_maj < σ_t(t) for a uniform
/// u, and where u·σ_maj < σ_min that is known without looking σ_t(t) up. The decisions, and so
/// the distances, are plain delta tracking's for the same numbers; lookups come at rate
/// σ_maj − σ_min, as in decomposition tracking (Kutz et al. 2017, "Spectral and Decomposition
/// Tracking for Rendering Heterogeneous Volumes", §4), whose control part at rate σ_min would
/// take one more exponential per flight. Returns the distance of the first real collision, or
/// NoCollision. sigmaT(t) gives σ_t at ray parameter t. The first two numbers (the first
/// exponential and its u) come from `first` when given (FlightNumbers), the others from rng.
/// Segments that `exact` prefers are crossed by regular tracking: the same budget E, spent on
/// the exact optical depth, ends in a real collision where it runs out (the memorylessness of
/// the exponential lets the two kinds of segment share it).
template <typename Segments, typename SigmaT, typename Exact = NoRegularTracking>
__attribute__((always_inline)) inline double deltaTrack(const Segments& segments,
                                                        const SigmaT& sigmaT, Rng& rngRef,
                                                        TrackingCounters& counters,
                                                        const Vec2* first = nullptr,
                                                        const Exact& exact = {}) {
    // Local copies (in registers: the caller's objects could alias the lookups' memory as far as
    // the compiler knows), written back at the end.
    FlightNumbers rng(rngRef, first);
    TrackingCounters c = counters;
    double hit = NoCollision;
    OpticalDepthBudget budget;
    segments([&](double t0, double t1, double sigmaMaj, double sigmaMin) {
        ++c.segments;
        if (!(sigmaMaj > 0) || !(t1 > t0)) return true;
        if constexpr (!std::is_same_v<Exact, NoRegularTracking>)
            if (exact.preferred(t0, t1, sigmaMaj - sigmaMin)) {
                double t;
                if (!exact.spend(t0, t1, budget.left(rng), &t, c)) return true;
                hit = t;
                return false;
            }
        const double invMaj = 1 / sigmaMaj;
        for (double t = t0; budget.next(sigmaMaj, invMaj, t1, rng, &t);) {
            const double uMaj = rng.uniform() * sigmaMaj;
            if (uMaj < sigmaMin) {  // real, and known to be without a lookup
                hit = t;
                return false;
            }
            ++c.densityLookups;
            if (uMaj < sigmaT(t)) {
                hit = t;
                return false;
            }
        }
        return true;
    });
    rngRef = rng.rng(), counters = c;
    return hit;
}

/// Residual ratio tracking (Novák, Selle & Jarosz 2014, "Residual Ratio Tracking for
/// Estimating Attenuation in Participating Media", §4), with the control part per segment:
/// T = Π_segments e^{−σ_min (t1 − t0)} Π_points (1 − (σ_t − σ_min)/(σ_maj − σ_min)), over
/// tentative points at rate σ_maj − σ_min. Roulette below T = rrThreshold keeps it unbiased:
/// survive with probability T/rrThreshold and continue with T = rrThreshold (the path's
/// survival-weight rule, rouletteSurvival, with its own threshold), else T = 0. Segments that
/// `exact` prefers multiply T by e^{−τ} of their exact optical depth τ.
template <typename Segments, typename SigmaT, typename Exact = NoRegularTracking>
__attribute__((always_inline)) inline double ratioTrack(const Segments& segments,
                                                        const SigmaT& sigmaT, Rng& rngRef,
                                                        TrackingCounters& counters,
                                                        const Exact& exact = {},
                                                        double rrThreshold = 0.1) {
    Rng rng = rngRef;  // local copies, as in deltaTrack
    TrackingCounters c = counters;
    double T = 1;
    auto roulette = [&] {
        if (T >= rrThreshold) return;
        T = rng.uniform() < rouletteSurvival(T, rrThreshold) ? rrThreshold : 0;
    };
    OpticalDepthBudget residual;
    segments([&](double t0, double t1, double sigmaMaj, double sigmaMin) {
        ++c.segments;
        if (!(sigmaMaj > 0) || !(t1 > t0)) return true;
        if constexpr (!std::is_same_v<Exact, NoRegularTracking>)
            if (exact.preferred(t0, t1, sigmaMaj - sigmaMin)) {
                // Past τ = 800, e^{−τ} is 0 in double: the walk can stop there.
                T *= std::exp(-exact.depth(t0, t1, c, 800));
                roulette();
                return T > 0;
            }
        if (sigmaMin > 0) {
            T *= std::exp(-sigmaMin * (t1 - t0));
            roulette();
        }
        const double sigmaRes = sigmaMaj - sigmaMin, invRes = 1 / sigmaRes;
        if (sigmaRes > 0)
            for (double t = t0; T > 0 && residual.next(sigmaRes, invRes, t1, rng, &t);) {
                ++c.densityLookups;
                T *= std::max(0.0, 1.0 - (sigmaT(t) - sigmaMin) * invRes);
                roulette();
            }
        return T > 0;
    });
    rngRef = rng, counters = c;
    return T;
}

/// Binary transmittance estimate by delta tracking: 1 if no real collision before the end.
template <typename Segments, typename SigmaT, typename Exact = NoRegularTracking>
double deltaTrackTransmittance(const Segments& segments, const SigmaT& sigmaT, Rng& rng,
                               TrackingCounters& c, const Exact& exact = {}) {
    return deltaTrack(segments, sigmaT, rng, c, nullptr, exact) == NoCollision ? 1.0 : 0.0;
}

}  // namespace shvol
