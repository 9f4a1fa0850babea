#include "shvol/media/majorant_grid.h"

#include <algorithm>

namespace shvol {

MajorantGrid::MajorantGrid(const Vec3& lo, const Vec3& hi, const Eigen::Vector3i& res)
    : lo_(lo), hi_(hi), res_(res.cwiseMax(1)) {
    cellSize_ = (hi_ - lo_).cwiseQuotient(res_.cast<double>());
    max_.assign(size_t(res_.x()) * res_.y() * res_.z(), 0.0);
}

void MajorantGrid::expand(const Vec3& bLo, const Vec3& bHi, double value) {
    int c0[3], c1[3];
    for (int a = 0; a < 3; ++a) {
        c0[a] = std::clamp(int(std::floor((bLo[a] - lo_[a]) / cellSize_[a])), 0, res_[a] - 1);
        c1[a] = std::clamp(int(std::floor((bHi[a] - lo_[a]) / cellSize_[a])), 0, res_[a] - 1);
    }
    for (int z = c0[2]; z <= c1[2]; ++z)
        for (int y = c0[1]; y <= c1[1]; ++y)
            for (int x = c0[0]; x <= c1[0]; ++x) {
                double& m = max_[index(x, y, z)];
                m = std::max(m, value);
            }
}

double MajorantGrid::at(const Vec3& p) const {
    if (max_.empty() || (p.array() < lo_.array()).any() || (p.array() > hi_.array()).any())
        return 0;
    int c[3];
    for (int a = 0; a < 3; ++a)
        c[a] = std::clamp(int(std::floor((p[a] - lo_[a]) / cellSize_[a])), 0, res_[a] - 1);
    return max_[index(c[0], c[1], c[2])];
}

double MajorantGrid::maxValue() const {
    return max_.empty() ? 0.0 : *std::max_element(max_.begin(), max_.end());
}

}  // namespace shvol
