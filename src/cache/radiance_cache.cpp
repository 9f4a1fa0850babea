#include "shvol/cache/radiance_cache.h"

#include <tbb/parallel_for.h>

#include "shvol/sh/hsh.h"

namespace shvol {

RadianceCache::RadianceCache(int order, double accuracy, const Vec3& lo, const Vec3& hi)
    : n_(order),
      a_(accuracy),
      diag_(std::max((hi - lo).norm(), 1e-300)),
      cell_(diag_ / 64),
      lo_(lo),
      rotation_(std::make_unique<const sh::HshRotation>(order)) {}

RadianceCache::~RadianceCache() = default;

double irradianceRelativeError(const std::vector<IncomingSample>& samples, double direct) {
    const size_t n = samples.size();
    if (n < 2) return 0;
    double sum = 0, sumSq = 0;
    for (const IncomingSample& s : samples) {
        const double y = s.L.mean() * s.w.z();
        sum += y, sumSq += y * y;
    }
    const double mean = sum / double(n), E = TwoPi * mean + std::max(0.0, direct);
    if (!(E > 0)) return 0;
    const double variance = std::max(0.0, (sumSq - sum * mean) / double(n - 1));
    return TwoPi * std::sqrt(variance / double(n)) / E;
}

std::vector<Vec3> RadianceCache::directions(int count, const std::vector<Vec2>& jitter) {
    // The first k² = ⌊√N⌋² samples tile the (z, φ) square in k × k strata, the rest are
    // uniform in all of it: every sample is uniformly distributed, so eq. 22's weight 2π/N holds.
    const int k = int(std::floor(std::sqrt(double(count))));
    std::vector<Vec3> w(count);
    for (int j = 0; j < count; ++j) {
        const bool stratum = j < k * k;
        const double u1 = stratum ? (j % k + jitter[j].x()) / k : jitter[j].x();
        const double u2 = stratum ? (j / k + jitter[j].y()) / k : jitter[j].y();
        w[j] = sphericalDirection2Pi(std::max(u1, 1e-9), u2);
    }
    return w;
}

int RadianceCache::sector(double x, double y) {
    const double turn = std::atan2(y, x) * Inv2Pi;  // in [−½, ½]
    return std::clamp(int(std::floor((turn + 0.5) * kSectors)), 0, kSectors - 1);
}

RadianceCache::Record RadianceCache::build(const Vec3& p, const Vec3& n,
                                           const std::vector<IncomingSample>& samples) const {
    const int nn = n_ * n_;
    const Frame frame(n);
    Record r{p,
             frame,
             n,
             0,
             std::vector<double>(3 * nn, 0.0),
             std::vector<double>(3 * nn, 0.0),
             std::vector<double>(3 * nn, 0.0)};
    // A hit seen edge-on (cos ξ = 0) or at P itself cannot be displaced: it counts as no hit.
    auto usable = [&](const IncomingSample& s) {
        if (!s.hit) return false;
        const Vec3 d = s.W - p;
        const double len = d.norm();
        return len > 0 && std::abs(s.nW.dot(d)) / len > 0;
    };
    double invDist = 0;
    int hits = 0;
    for (const IncomingSample& s : samples)
        if (usable(s)) invDist += 1 / (s.W - p).norm(), ++hits;
    r.R = std::clamp(hits > 0 && invDist > 0 ? hits / invDist : 0.25 * diag_, 0.01 * diag_,
                     0.25 * diag_);
    // What lies beside the record in its tangent plane, sector by sector: the hits within 45° of
    // the plane (a hit straight above it, a ceiling, is no obstacle beside it) on surfaces
    // that stand across it, their normals more than 30° from the record's (inside a bowl, its own
    // surface rising ahead is met near the record by the lowest rays, and more rays shut the
    // cache off: 278 of 1024 lookups answered at 1024 rays per record; review).
    r.clear.fill(std::numeric_limits<float>::infinity());
    for (const IncomingSample& s : samples)
        if (usable(s) && !(std::abs(s.nW.dot(n)) >= kMinGeometricCos)) {
            const Vec3 l = frame.toLocal(s.W - p);
            const double h = std::hypot(l.x(), l.y());
            if (!(std::abs(l.z()) <= h)) continue;
            float& c = r.clear[sector(l.x(), l.y())];
            c = std::min(c, float(h));
        }
    // The displaced-point quadrature gives nothing to the directions a displacement uncovers
    // behind an occluder: taken of L, it assumes they are black. The gradients are taken of
    // L − c instead, which assumes the uncovered directions show radiance c: what lies behind
    // the occluders, as far as one number can tell. With samples that met no surface (and did
    // not dip below it), c is their mean radiance, the background's: exact for a constant
    // background (a white furnace with an occluder had gradients of a constant, and came out up
    // to 1.1% off 1 at a = 0.25 and 9.8% at a = 1), and 0 for a black one. A record that sees the
    // background in fewer than half its rays that are not below its surface, or none, takes the
    // mean of the farther half of its hits, which lie behind the nearer: exact for constant
    // radiance there too. (Under a shelf 0.02 above a floor, the sky seen through the opening in a
    // few per cent of the rays made gradients of L − sky that, extrapolated where the radiance
    // falls off like 1/x, put the floor deep inside 10–50 times too bright, +15.6% over the image;
    // helper 105.) (With c = 0, as until 4 Dec, a render inside an emitting shell with an occluder
    // had twice the error: RMSE 0.017 against 0.0089 at a = 1, HSH order 20; README). (It is not a
    // control variate: the estimate's expectation changes with c. The mean of all samples, tried
    // first, was 26% low for a lit occluder against a black background.)
    Spectrum background = Spectrum::Zero(), c = Spectrum::Zero();
    int misses = 0, seen = 0;
    for (const IncomingSample& s : samples) {
        if (!s.hit && !s.below) background += s.L, ++misses;
        seen += !s.below;
    }
    if (2 * misses >= seen && misses > 0) {
        c = background / double(misses);
    } else {
        // (squared distance, index: ties go by index, the same on every standard library)
        std::vector<std::pair<double, size_t>> byDistance;
        for (size_t k = 0; k < samples.size(); ++k)
            if (samples[k].hit) byDistance.push_back({(samples[k].W - p).squaredNorm(), k});
        const size_t half = byDistance.size() / 2;
        std::nth_element(byDistance.begin(), byDistance.begin() + half, byDistance.end());
        for (size_t k = half; k < byDistance.size(); ++k) c += samples[byDistance[k].second].L;
        if (byDistance.size() > half) c /= double(byDistance.size() - half);
    }
    const double scale = TwoPi / samples.size();
    const double delta = 1e-3 * r.R;  // Δx of the finite differences
    const Vec3 moved[2] = {p + delta * frame.s, p + delta * frame.t};
    // The sums of eq. 22 and of the displaced estimates, over blocks of kBlock samples in
    // parallel, the blocks' sums then added in order: the same numbers for any thread count.
    constexpr size_t kBlock = 64;
    const size_t blocks = (samples.size() + kBlock - 1) / kBlock, stride = 9 * size_t(nn);
    std::vector<double> partial(blocks * stride, 0.0);  // per block: λ, Δx·∂λ/∂x, Δx·∂λ/∂y
    tbb::parallel_for(size_t(0), blocks, [&](size_t block) {
        double* sums[3] = {&partial[block * stride], &partial[block * stride + 3 * nn],
                           &partial[block * stride + 6 * nn]};
        std::vector<double> h(nn);
        // out += weight·L·H(ω), H(ω) as last evaluated into h.
        auto accumulate = [&](double* out, double weight, const Spectrum& L) {
            for (int c = 0; c < 3; ++c)
                for (int i = 0; i < nn; ++i) out[c * nn + i] += scale * weight * L[c] * h[i];
        };
        for (size_t k = block * kBlock; k < std::min(samples.size(), (block + 1) * kBlock); ++k) {
            const IncomingSample& s = samples[k];
            const bool up = s.w.z() > 0;
            if (up) {
                sh::hshEval(n_, s.w, h.data());
                accumulate(sums[0], 1, s.L);
            }
            if (!usable(s)) continue;  // not displaced: the same term in λ and λ′
            const Vec3 d = s.W - p;
            // Nor is a hit whose surface's plane passes within 10 Δx of P (a record on an edge,
            // the adjacent face's hits): the reprojection's Jacobian, cos ξ′/cos ξ, is a first-
            // order estimate only while Δx is small against that distance, |n_W·d|, and it is
            // unbounded as |n_W·d| → 0 (10¹³ from a hit 10⁻¹⁷ off the plane by rounding).
            if (std::abs(s.nW.dot(d)) <= 10 * delta) continue;
            const Spectrum dL = s.L - c;
            if (up) accumulate(sums[1], -1, dL), accumulate(sums[2], -1, dL);  // − its term in λ
            const double cosXi = std::abs(s.nW.dot(d)) / d.norm();
            for (int axis = 0; axis < 2; ++axis) {
                const Vec3 d2 = s.W - moved[axis];
                const Vec3 w2 = frame.toLocal(d2.normalized());
                const double cosXi2 = std::abs(s.nW.dot(d2)) / d2.norm();
                const double weight = d.squaredNorm() * cosXi2 / (d2.squaredNorm() * cosXi);
                if (!(w2.z() > 0) || !(weight > 0)) continue;
                sh::hshEval(n_, w2, h.data());
                accumulate(sums[1 + axis], weight, dL);  // + its term in λ′
            }
        }
    });
    for (size_t block = 0; block < blocks; ++block)
        for (int i = 0; i < 3 * nn; ++i) {
            r.lambda[i] += partial[block * stride + i];
            r.dx[i] += partial[block * stride + 3 * nn + i];
            r.dy[i] += partial[block * stride + 6 * nn + i];
        }
    for (int i = 0; i < 3 * nn; ++i) {
        r.dx[i] /= delta;
        r.dy[i] /= delta;
    }
    return r;
}

Eigen::Vector3i RadianceCache::cellOf(const Vec3& p, int level) const {
    return ((p - lo_) / std::ldexp(cell_, level)).array().floor().cast<int>();
}

uint64_t RadianceCache::cellKey(const Eigen::Vector3i& c, int level) const {
    // 19 bits per axis and 7 for the level (cells beyond ±2^18 of the box alias, which only
    // costs candidates).
    auto b = [](int v) { return uint64_t(uint32_t(v) & 0x7FFFFu); };
    return b(c.x()) | (b(c.y()) << 19) | (b(c.z()) << 38) | (uint64_t(level) << 57);
}

void RadianceCache::add(const Vec3& p, const Vec3& n, const Vec3& ng,
                        const std::vector<IncomingSample>& samples) {
    records_.push_back(build(p, n, samples));
    records_.back().ng = ng;
    const Record& r = records_.back();
    // The level whose cells are at least as wide as the record's reach a·R: it touches at most
    // 3 × 3 × 3 of them, whatever a and R.
    const double reach = a_ * r.R;
    int level = 0;
    while (level + 1 < kLevels && std::ldexp(cell_, level) < reach) ++level;
    usedLevels_ |= 1u << level;
    const Eigen::Vector3i c0 = cellOf(p - Vec3::Constant(reach), level);
    const Eigen::Vector3i c1 = cellOf(p + Vec3::Constant(reach), level);
    for (int z = c0.z(); z <= c1.z(); ++z)
        for (int y = c0.y(); y <= c1.y(); ++y)
            for (int x = c0.x(); x <= c1.x(); ++x)
                grid_[cellKey({x, y, z}, level)].push_back(uint32_t(records_.size() - 1));
}

double RadianceCache::weight(const Record& r, const Vec3& p, const Vec3& n) const {
    const double d = (p - r.p).norm() / r.R + std::sqrt(std::max(0.0, 1 - n.dot(r.frame.n)));
    return d > 0 ? 1 / d : std::numeric_limits<double>::infinity();
}

double RadianceCache::servingWeight(const Record& r, const Vec3& p, const Vec3& n,
                                    const Vec3& ng) const {
    if (!(ng.dot(r.ng) >= kMinGeometricCos)) return 0;
    const double w = weight(r, p, n);
    if (!(w > 1 / a_)) return 0;
    // Not past a surface its rays met beside it, in the query's sector or either next to it.
    const Vec3 d = p - r.p;
    const double x = d.dot(r.frame.s), y = d.dot(r.frame.t);
    const int k = sector(x, y);
    const float clear = std::min({r.clear[size_t(k)], r.clear[size_t((k + 1) % kSectors)],
                                  r.clear[size_t((k + kSectors - 1) % kSectors)]});
    return std::hypot(x, y) < clear ? w : 0;
}

template <typename Visit>
void RadianceCache::candidates(const Vec3& p, Visit visit) const {
    // The levels some record is listed on, lowest first: no hash lookup where none is.
    for (uint32_t left = usedLevels_; left; left &= left - 1) {
        const int level = __builtin_ctz(left);
        const auto it = grid_.find(cellKey(cellOf(p, level), level));
        if (it != grid_.end())
            for (uint32_t i : it->second) visit(records_[i]);
    }
}

bool RadianceCache::covers(const Vec3& p, const Vec3& n, const Vec3& ng) const {
    bool covered = false;
    candidates(p, [&](const Record& r) { covered = covered || servingWeight(r, p, n, ng) > 0; });
    return covered;
}

bool RadianceCache::lookup(const Vec3& p, const Vec3& n, const Vec3& ng, double* lambda) const {
    const int nn = n_ * n_;
    std::fill(lambda, lambda + 3 * nn, 0.0);
    // Scratch (lookups run once per pixel sample): a record's coefficients moved to p, and the
    // weighted sum of the rotated records' SH corrections (sh::HshRotation: h′ = h + C (D − I) E h;
    // C is linear, so one SH→HSH projection per lookup rather than one per rotated record).
    thread_local std::vector<double> moved, shSum;
    moved.resize(3 * nn);
    shSum.resize(3 * size_t(rotation_->shCount()));
    bool rotated = false;  // (shSum is zeroed by the first rotated record)
    double wSum = 0;
    const Frame query(n);
    candidates(p, [&](const Record& r) {
        double w = servingWeight(r, p, n, ng);
        if (!(w > 0)) return;
        w = std::min(w, 1e12);  // a query exactly at a record
        wSum += w;
        const Frame& frame = r.frame;
        const double dx = (p - r.p).dot(frame.s), dy = (p - r.p).dot(frame.t);
        // Coefficient k of the record moved to p by its gradients.
        auto at = [&](int k) { return r.lambda[k] + dx * r.dx[k] + dy * r.dy[k]; };
        for (int k = 0; k < 3 * nn; ++k) moved[k] = at(k);
        for (int k = 0; k < 3 * nn; ++k) lambda[k] += w * moved[k];
        if (!((r.frame.n - n).squaredNorm() > 1e-24)) return;  // the query's frame
        // Rotated from the record's frame onto the query's: the correction, the three channels
        // together (it vanishes as the frames meet, so the two branches join continuously).
        Eigen::Matrix3d R;
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                R(a, b) = (a == 0   ? query.s
                           : a == 1 ? query.t
                                    : query.n)
                              .dot(b == 0   ? frame.s
                                   : b == 1 ? frame.t
                                            : frame.n);
        if (!rotated) std::fill(shSum.begin(), shSum.end(), 0.0);
        rotated = true;
        rotation_->addCorrection(R, moved.data(), w, shSum.data(), 3);
    });
    if (rotated) rotation_->finish(shSum.data(), lambda, 3);
    if (!(wSum > 0)) return false;
    const double invSum = 1 / wSum;
    for (int k = 0; k < 3 * nn; ++k) lambda[k] *= invSum;
    return true;
}

size_t RadianceCache::memoryBytes() const {
    size_t b = records_.capacity() * sizeof(Record);
    for (const Record& r : records_) b += 3 * r.lambda.capacity() * sizeof(double);
    for (const auto& [key, list] : grid_) b += sizeof(key) + list.capacity() * sizeof(uint32_t);
    return b;
}

}  // namespace shvol
