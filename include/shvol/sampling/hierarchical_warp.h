#pragma once
/// \file Hierarchical sample warping (Clarberg et al. 2005, "Wavelet importance sampling";
/// Jarosz et al. 2009 §3.2) over the cylindrical domain (z, φ) ∈ [−1, 1] × [0, 2π).
///
/// The domain is a quadtree: a node [z0, z1] × [φ0, φ1] has four children, c[2r + k] with r = 0
/// the lower z half and k = 0 the lower φ half. At each node a point u ∈ [0, 1)² (its position
/// inside the node) is first split by the row marginal P(r) = (c[2r] + c[2r+1]) / Σc, then by the
/// conditional P(k | r) = c[2r+k] / (c[2r] + c[2r+1]), and rescaled to its position inside the
/// chosen child. After `depth` levels the point is placed in its leaf at its remaining position.
///
/// Node masses are clamped at 0 before the split, so negative regions of a reconstruction get no
/// samples. The density of the result is exactly
///   pdf(z, φ) = Π_levels c[chosen] / Σc  ÷  ((z1 − z0)(φ1 − φ0))_leaf,
/// which is what the functions below return: the true density of the warp, with or without
/// clamping. Since dω = dz dφ, this is also the density over solid angle.
///
/// The map is the same for every point, so warping a point set applies it pointwise and
/// preserves the set's stratification; warpPoints() shares each node's masses between the points
/// that pass through it, which matters when the masses are computed on the fly.
///
/// `Children` is any callable `void(const WarpNode&, double c[4])` giving the (unnormalised)
/// integrals of the target over the four children of a node.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "shvol/core/math.h"

namespace shvol {

struct WarpNode {
    int level = 0;
    int iz = 0, iphi = 0;  ///< cell index at this level (2^level cells per axis)
    double z0 = -1, z1 = 1, phi0 = 0, phi1 = TwoPi;

    double zMid() const { return 0.5 * (z0 + z1); }
    double phiMid() const { return 0.5 * (phi0 + phi1); }
    WarpNode child(int r, int k) const {
        WarpNode c{level + 1, 2 * iz + r, 2 * iphi + k, z0, z1, phi0, phi1};
        (r ? c.z0 : c.z1) = zMid();
        (k ? c.phi0 : c.phi1) = phiMid();
        return c;
    }
    double area() const { return (z1 - z0) * (phi1 - phi0); }
};

struct WarpSample {
    double z = 0, phi = 0;
    double pdf = 0;  ///< 0 when the target has no positive mass (the sample is then invalid)
    Vec3 direction() const { return sphericalDirection(z, phi); }
};

/// A direction with the value of the sampled function there and the pdf of having drawn it (the
/// samplers' sample(); their warp() gives a WarpSample, without the value).
struct SphereSample {
    Vec3 w{0, 0, 1};
    double value = 0;  ///< the sampled function at w (each sampler says which function)
    double pdf = 0;    ///< solid-angle density of the sampler at w; 0 marks a failed sample
};

/// A warp's sample with value(direction) as its value; a failed draw (pdf not > 0) keeps its pdf,
/// with value 0.
template <class Value>
SphereSample withValue(const WarpSample& s, Value&& value) {
    if (!(s.pdf > 0)) return {Vec3(0, 0, 1), 0, s.pdf};
    const Vec3 w = s.direction();
    return {w, value(w), s.pdf};
}

namespace detail {
/// Clamped masses of one node and its split probabilities.
struct Split {
    double c[4], total, pRow0, pCol0[2];
    explicit Split(const double raw[4]) {
        for (int i = 0; i < 4; ++i) c[i] = raw[i] > 0 ? raw[i] : 0.0;
        const double row0 = c[0] + c[1], row1 = c[2] + c[3];
        total = row0 + row1;
        pRow0 = total > 0 ? row0 / total : 0;
        pCol0[0] = row0 > 0 ? c[0] / row0 : 0;
        pCol0[1] = row1 > 0 ? c[2] / row1 : 0;
    }
};
/// Chooses a side with probability p for side 0 and rescales x to the chosen side.
inline int choose(double p, double& x) {
    constexpr double OneMinus = 1.0 - 0x1.0p-53;
    int side;
    if (x < p) {
        side = 0;
        x /= p;
    } else {
        side = 1;
        x = (x - p) / (1 - p);
    }
    x = std::clamp(x, 0.0, OneMinus);
    return side;
}
}  // namespace detail

/// Warps one point u ∈ [0, 1)².
template <class Children>
WarpSample hierarchicalWarp(const Children& children, int depth, Vec2 u) {
    WarpNode node;
    double prob = 1, raw[4];
    for (int d = 0; d < depth; ++d) {
        children(node, raw);
        const detail::Split s(raw);
        if (!(s.total > 0)) return {};
        const int r = detail::choose(s.pRow0, u.x());
        const int k = detail::choose(s.pCol0[r], u.y());
        prob *= s.c[2 * r + k] / s.total;
        node = node.child(r, k);
    }
    return {node.z0 + u.x() * (node.z1 - node.z0), node.phi0 + u.y() * (node.phi1 - node.phi0),
            prob / node.area()};
}

/// The density hierarchicalWarp produces at (z, φ).
template <class Children>
double hierarchicalPdf(const Children& children, int depth, double z, double phi) {
    WarpNode node;
    double prob = 1, raw[4];
    for (int d = 0; d < depth; ++d) {
        children(node, raw);
        const detail::Split s(raw);
        const int r = z >= node.zMid(), k = phi >= node.phiMid();
        if (!(s.c[2 * r + k] > 0)) return 0;
        prob *= s.c[2 * r + k] / s.total;
        node = node.child(r, k);
    }
    return prob / node.area();
}

/// The probability that hierarchicalWarp lands in the rectangle [z0, z1] × [φ0, φ1]: descends
/// only into nodes that straddle the rectangle's edges; a leaf straddling an edge contributes in
/// proportion to its overlap (the density is uniform on a leaf). Exact, for chi² expected counts.
template <class Children>
double hierarchicalProbability(const Children& children, int depth, double z0, double z1,
                               double phi0, double phi1) {
    struct Rec {
        const Children& children;
        int depth;
        double z0, z1, p0, p1;
        double operator()(const WarpNode& node, double prob) const {
            const double oz = std::min(z1, node.z1) - std::max(z0, node.z0);
            const double op = std::min(p1, node.phi1) - std::max(p0, node.phi0);
            if (!(oz > 0) || !(op > 0) || !(prob > 0)) return 0;
            const bool inside =
                z0 <= node.z0 && node.z1 <= z1 && p0 <= node.phi0 && node.phi1 <= p1;
            if (inside) return prob;
            if (node.level == depth) return prob * oz * op / node.area();
            double raw[4];
            children(node, raw);
            const detail::Split s(raw);
            if (!(s.total > 0)) return 0;
            double sum = 0;
            for (int r = 0; r < 2; ++r)
                for (int k = 0; k < 2; ++k)
                    sum += (*this)(node.child(r, k), prob * s.c[2 * r + k] / s.total);
            return sum;
        }
    };
    return Rec{children, depth, z0, z1, phi0, phi1}(WarpNode{}, 1.0);
}

/// Warps a whole point set (e.g. stratified or low-discrepancy) top-down: each visited node's
/// masses are computed once for all the points inside it. out[i] is the image of u[i], identical
/// to hierarchicalWarp(children, depth, u[i]).
template <class Children>
void hierarchicalWarpPoints(const Children& children, int depth, const Vec2* u, int count,
                            WarpSample* out) {
    std::vector<Vec2> local(u, u + count);
    std::vector<char> side(count);
    std::vector<int> index(count);
    std::iota(index.begin(), index.end(), 0);
    struct Rec {
        const Children& children;
        int depth;
        std::vector<Vec2>& local;
        std::vector<char>& side;
        WarpSample* out;
        void operator()(const WarpNode& node, double prob, int* begin, int* end) const {
            if (begin == end) return;
            if (node.level == depth) {
                for (int* i = begin; i != end; ++i) {
                    const Vec2& p = local[*i];
                    out[*i] = {node.z0 + p.x() * (node.z1 - node.z0),
                               node.phi0 + p.y() * (node.phi1 - node.phi0), prob / node.area()};
                }
                return;
            }
            double raw[4];
            children(node, raw);
            const detail::Split s(raw);
            if (!(s.total > 0)) {
                for (int* i = begin; i != end; ++i) out[*i] = {};
                return;
            }
            // Rows: choose and rescale z once per point, then partition by the choice; then the
            // same for φ within each row. (std::partition may call its predicate more than once.)
            for (int* i = begin; i != end; ++i)
                side[*i] = char(detail::choose(s.pRow0, local[*i].x()));
            int* rowSplit = std::partition(begin, end, [&](int i) { return side[i] == 0; });
            int* rows[3] = {begin, rowSplit, end};
            for (int r = 0; r < 2; ++r) {
                for (int* i = rows[r]; i != rows[r + 1]; ++i)
                    side[*i] = char(detail::choose(s.pCol0[r], local[*i].y()));
                int* colSplit =
                    std::partition(rows[r], rows[r + 1], [&](int i) { return side[i] == 0; });
                int* cols[3] = {rows[r], colSplit, rows[r + 1]};
                for (int k = 0; k < 2; ++k)
                    (*this)(node.child(r, k), prob * (s.c[2 * r + k] / s.total), cols[k],
                            cols[k + 1]);
            }
        }
    };
    Rec{children, depth, local, side, out}(WarpNode{}, 1.0, index.data(), index.data() + count);
}

}  // namespace shvol
