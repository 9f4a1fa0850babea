#pragma once
/// \file A coarse grid of maximum densities, built once at load, walked by a 3D DDA.
///
/// Each cell stores an upper bound of the density anywhere inside it (including the reach of
/// trilinear interpolation), so delta and ratio tracking can use a local majorant per cell: empty
/// cells cost one DDA step and no density lookup (pbrt-v4's DDAMajorantIterator does the same;
/// the traversal is Amanatides & Woo 1987).
#include <Eigen/Core>
#include <vector>

#include "shvol/core/math.h"

namespace shvol {

class MajorantGrid {
  public:
    MajorantGrid() = default;
    /// res cells covering the box [lo, hi] of the medium's own (index) space.
    MajorantGrid(const Vec3& lo, const Vec3& hi, const Eigen::Vector3i& res);

    /// max-accumulates value into every cell overlapping the closed box [bLo, bHi].
    void expand(const Vec3& bLo, const Vec3& bHi, double value);
    /// Lower bounds of the density per cell, in index order (x fastest); empty: 0 everywhere.
    void setMinimum(std::vector<double> minimum) { min_ = std::move(minimum); }
    /// The box [lo, hi] of cell (x, y, z).
    Vec3 cellLower(int x, int y, int z) const {
        return lo_ + Vec3(x, y, z).cwiseProduct(cellSize_);
    }
    Vec3 cellUpper(int x, int y, int z) const { return cellLower(x + 1, y + 1, z + 1); }
    double cell(int x, int y, int z) const { return max_[index(x, y, z)]; }
    const Eigen::Vector3i& resolution() const { return res_; }
    const Vec3& lower() const { return lo_; }
    const Vec3& upper() const { return hi_; }
    double maxValue() const;
    bool empty() const { return max_.empty(); }
    /// The value of the cell containing p (0 outside the grid).
    double at(const Vec3& p) const;

    /// Visits, in order, the segments [t0, t1) of the ray o + t·d (d need not be unit length)
    /// inside the grid and [tMin, tMax], as visit(t0, t1, cellMax, cellMin) → bool; false stops
    /// the walk.
    template <typename Visit>
    void traverse(const Vec3& o, const Vec3& d, double tMin, double tMax, Visit&& visit) const;

  private:
    size_t index(int x, int y, int z) const { return (size_t(z) * res_.y() + y) * res_.x() + x; }
    Vec3 lo_{0, 0, 0}, hi_{0, 0, 0}, cellSize_{1, 1, 1};
    Eigen::Vector3i res_{0, 0, 0};
    std::vector<double> max_, min_;
};

template <typename Visit>
void MajorantGrid::traverse(const Vec3& o, const Vec3& d, double tMin, double tMax,
                            Visit&& visit) const {
    if (max_.empty()) return;
    // Clip to the grid's box.
    double t0 = tMin, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        const double inv = 1.0 / d[a];
        double tn = (lo_[a] - o[a]) * inv, tf = (hi_[a] - o[a]) * inv;
        if (tn > tf) std::swap(tn, tf);
        if (tn > t0) t0 = tn;
        if (tf < t1) t1 = tf;
    }
    if (!(t0 < t1)) return;
    int cell[3], step[3], end[3];
    double tNext[3], dt[3];
    const Vec3 p = o + t0 * d;
    for (int a = 0; a < 3; ++a) {
        cell[a] = std::clamp(int(std::floor((p[a] - lo_[a]) / cellSize_[a])), 0, res_[a] - 1);
        if (d[a] == 0) {
            step[a] = 0, end[a] = -2, tNext[a] = INFINITY, dt[a] = INFINITY;
            continue;
        }
        const bool pos = d[a] > 0;
        step[a] = pos ? 1 : -1;
        end[a] = pos ? res_[a] : -1;
        tNext[a] = (lo_[a] + (cell[a] + (pos ? 1 : 0)) * cellSize_[a] - o[a]) / d[a];
        dt[a] = cellSize_[a] / std::abs(d[a]);
    }
    double t = t0;
    for (;;) {
        const int a =
            tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
        const double tEnd = std::min(tNext[a], t1);
        const size_t i = index(cell[0], cell[1], cell[2]);
        if (tEnd > t && !visit(t, tEnd, max_[i], min_.empty() ? 0.0 : min_[i])) return;
        if (tEnd >= t1) return;
        t = std::max(t, tEnd);  // an entry cell misassigned by rounding must not step back
        cell[a] += step[a];
        if (cell[a] == end[a]) return;
        tNext[a] += dt[a];
    }
}

}  // namespace shvol
