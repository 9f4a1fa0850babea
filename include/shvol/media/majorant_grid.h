#pragma once
/// \file A coarse grid of maximum densities, built once at load, walked by a 3D DDA.
///
/// Each cell stores an upper bound of the density anywhere inside it (including the reach of
/// trilinear interpolation), so delta and ratio tracking can use a local majorant per cell: empty
/// cells cost one DDA step and no density lookup (pbrt-v4's DDAMajorantIterator does the same;
/// the traversal is Amanatides & Woo 1987).
#include <Eigen/Core>
#include <utility>
#include <vector>

#include "shvol/core/math.h"

namespace shvol {

class MajorantGrid {
  public:
    MajorantGrid() = default;
    /// res cells covering the box [lo, hi] of the medium's own (index) space.
    MajorantGrid(const Vec3& lo, const Vec3& hi, const Eigen::Vector3i& res);

    /// Cells of edge `cell` from lo, ⌈(hi − lo)/cell⌉ of them per axis, over the box [lo, hi]: the
    /// part of the last cells beyond hi is outside the grid, as for coarsened().
    static MajorantGrid withCells(const Vec3& lo, const Vec3& hi, double cell);

    /// max-accumulates value into every cell overlapping the closed box [bLo, bHi].
    void expand(const Vec3& bLo, const Vec3& bHi, double value);
    /// Lower bounds of the density per cell, in index order (x fastest); empty: 0 everywhere.
    void setMinimum(const std::vector<double>& minimum);
    /// The box [lo, hi] of cell (x, y, z).
    Vec3 cellLower(int x, int y, int z) const {
        return lo_ + Vec3(x, y, z).cwiseProduct(cellSize_);
    }
    Vec3 cellUpper(int x, int y, int z) const { return cellLower(x + 1, y + 1, z + 1); }
    double cell(int x, int y, int z) const { return cells_[index(x, y, z)].max; }
    const Eigen::Vector3i& resolution() const { return res_; }
    const Vec3& lower() const { return lo_; }
    const Vec3& upper() const { return hi_; }
    double maxValue() const;
    bool empty() const { return cells_.empty(); }
    /// The value of the cell containing p (0 outside the grid).
    double at(const Vec3& p) const;

    /// The grid with cells twice as large on every axis, ⌈res/2⌉ of them from the same lower
    /// corner, over the same box [lo, hi]: traverse and at treat the part of the last cells
    /// beyond hi as outside the grid (walked, it would cost tentative collisions where there is
    /// no density: one cell over the whole medium would double its box on every axis). Each cell
    /// holds the largest value of the cells it covers, which is what expand() with the same boxes
    /// would have given it. Lower bounds are not carried over.
    MajorantGrid coarsened() const;

    /// The expected cost of tracking along lines through the grid, mean over `rays` (origin and
    /// direction in the grid's space, the direction's length setting the units of t):
    ///   segmentCost · (segments visited) + scale · ∫ cellMax dt,
    /// the second term being the expected number of tentative collisions at rate scale·cellMax.
    /// Whole lines are counted (t from −∞ to ∞), not rays.
    double trackingCost(const std::vector<std::pair<Vec3, Vec3>>& rays, double scale,
                        double segmentCost) const;

    /// Visits, in order, the segments [t0, t1) of the ray o + t·d (d need not be unit length)
    /// inside the grid and [tMin, tMax], as visit(t0, t1, cellMax, cellMin) → bool; false stops
    /// the walk.
    template <typename Visit>
    void traverse(const Vec3& o, const Vec3& d, double tMin, double tMax, Visit&& visit) const;

  private:
    size_t index(int x, int y, int z) const { return (size_t(z) * res_.y() + y) * res_.x() + x; }
    Vec3 lo_{0, 0, 0}, hi_{0, 0, 0}, cellSize_{1, 1, 1}, invCellSize_{1, 1, 1};
    Eigen::Vector3i res_{0, 0, 0};
    /// Per cell, x fastest: the upper and the lower bound of the density (min 0 until
    /// setMinimum), rounded outward to float (floatAtLeast, floatAtMost): exact for the
    /// densities of a float VDB grid, and still bounds for any double. Half the memory of
    /// doubles, which the one-voxel grid the cell-size choice builds over a large box feels at
    /// load (page faults).
    struct Bounds {
        float max = 0, min = 0;
    };
    std::vector<Bounds> cells_;
};

template <typename Visit>
void MajorantGrid::traverse(const Vec3& o, const Vec3& d, double tMin, double tMax,
                            Visit&& visit) const {
    if (cells_.empty()) return;
    // Clip to the grid's box. Three divisions per ray; everything after them multiplies.
    const Vec3 invD = d.cwiseInverse();
    double t0 = tMin, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        double tn = (lo_[a] - o[a]) * invD[a], tf = (hi_[a] - o[a]) * invD[a];
        if (tn > tf) std::swap(tn, tf);
        if (tn > t0) t0 = tn;
        if (tf < t1) t1 = tf;
    }
    if (!(t0 < t1)) return;
    // The walk keeps its state in scalars (an axis-indexed array would live on the stack and
    // every step would wait on a store), and the cell as one linear index.
    int cell[3], left[3];
    double tNext[3], dt[3];
    ptrdiff_t stride[3] = {1, res_.x(), ptrdiff_t(res_.x()) * res_.y()};
    const Vec3 p = o + t0 * d;
    for (int a = 0; a < 3; ++a) {
        cell[a] = std::clamp(floorToInt((p[a] - lo_[a]) * invCellSize_[a]), 0, res_[a] - 1);
        const bool pos = d[a] > 0;
        left[a] = pos ? res_[a] - 1 - cell[a] : cell[a];  // steps before leaving the grid
        if (!pos) stride[a] = -stride[a];
        tNext[a] = d[a] == 0 ? INFINITY
                             : (lo_[a] + (cell[a] + (pos ? 1 : 0)) * cellSize_[a] - o[a]) * invD[a];
        dt[a] = d[a] == 0 ? INFINITY : cellSize_[a] * std::abs(invD[a]);
    }
    double tx = tNext[0], ty = tNext[1], tz = tNext[2];
    int lx = left[0], ly = left[1], lz = left[2];
    const Bounds* c = cells_.data() + index(cell[0], cell[1], cell[2]);
    double t = t0;
    for (;;) {
        const double tEnd = std::min(std::min(tx, ty), std::min(tz, t1));
        if (tEnd > t && !visit(t, tEnd, c->max, c->min)) return;
        if (tEnd >= t1) return;
        t = std::max(t, tEnd);  // an entry cell misassigned by rounding must not step back
        if (tx <= ty && tx <= tz) {
            if (--lx < 0) return;
            c += stride[0], tx += dt[0];
        } else if (ty <= tz) {
            if (--ly < 0) return;
            c += stride[1], ty += dt[1];
        } else {
            if (--lz < 0) return;
            c += stride[2], tz += dt[2];
        }
    }
}

}  // namespace shvol
