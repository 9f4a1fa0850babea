#include "shvol/media/majorant_grid.h"

#include <algorithm>
#include <cmath>

namespace shvol {

MajorantGrid::MajorantGrid(const Vec3& lo, const Vec3& hi, const Eigen::Vector3i& res)
    : lo_(lo), hi_(hi), res_(res.cwiseMax(1)) {
    cellSize_ = (hi_ - lo_).cwiseQuotient(res_.cast<double>());
    invCellSize_ = cellSize_.cwiseInverse();
    cells_.assign(size_t(res_.x()) * res_.y() * res_.z(), Bounds{});
}

MajorantGrid MajorantGrid::withCells(const Vec3& lo, const Vec3& hi, double cell) {
    const Eigen::Vector3i res = ((hi - lo) / cell).array().ceil().cast<int>().max(1);
    MajorantGrid g(lo, lo + cell * res.cast<double>(), res);
    g.hi_ = hi;
    return g;
}

void MajorantGrid::expand(const Vec3& bLo, const Vec3& bHi, double value) {
    const float upper = floatAtLeast(value);
    int c0[3], c1[3];
    for (int a = 0; a < 3; ++a) {
        c0[a] = std::clamp(int(std::floor((bLo[a] - lo_[a]) / cellSize_[a])), 0, res_[a] - 1);
        c1[a] = std::clamp(int(std::floor((bHi[a] - lo_[a]) / cellSize_[a])), 0, res_[a] - 1);
    }
    for (int z = c0[2]; z <= c1[2]; ++z)
        for (int y = c0[1]; y <= c1[1]; ++y)
            for (int x = c0[0]; x <= c1[0]; ++x) {
                float& m = cells_[index(x, y, z)].max;
                m = std::max(m, upper);
            }
}

double MajorantGrid::at(const Vec3& p) const {
    if (cells_.empty() || (p.array() < lo_.array()).any() || (p.array() > hi_.array()).any())
        return 0;
    int c[3];
    for (int a = 0; a < 3; ++a)
        c[a] = std::clamp(int(std::floor((p[a] - lo_[a]) / cellSize_[a])), 0, res_[a] - 1);
    return cells_[index(c[0], c[1], c[2])].max;
}

MajorantGrid MajorantGrid::coarsened() const {
    const Eigen::Vector3i res = (res_ + Eigen::Vector3i::Ones()) / 2;
    MajorantGrid g(lo_, lo_ + 2 * cellSize_.cwiseProduct(res.cast<double>()), res);
    g.hi_ = hi_;  // the same box: no walk or lookup reaches the last cells' part beyond it
    for (int z = 0; z < res_.z(); ++z)
        for (int y = 0; y < res_.y(); ++y)
            for (int x = 0; x < res_.x(); ++x) {
                float& m = g.cells_[g.index(x / 2, y / 2, z / 2)].max;
                m = std::max(m, cells_[index(x, y, z)].max);
            }
    return g;
}

double MajorantGrid::trackingCost(const std::vector<std::pair<Vec3, Vec3>>& rays, double scale,
                                  double segmentCost) const {
    double cost = 0;
    for (const auto& [o, d] : rays)
        traverse(o, d, -INFINITY, INFINITY, [&](double t0, double t1, double m, double) {
            cost += segmentCost + scale * m * (t1 - t0);
            return true;
        });
    return rays.empty() ? 0 : cost / double(rays.size());
}

void MajorantGrid::setMinimum(const std::vector<double>& minimum) {
    for (size_t i = 0; i < cells_.size() && i < minimum.size(); ++i)
        cells_[i].min = floatAtMost(minimum[i]);
}

double MajorantGrid::maxValue() const {
    double m = 0;
    for (const Bounds& b : cells_) m = std::max(m, double(b.max));
    return m;
}

}  // namespace shvol
