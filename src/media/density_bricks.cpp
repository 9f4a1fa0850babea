#include "shvol/media/density_bricks.h"

namespace shvol {

DensityBricks::DensityBricks(const Eigen::Vector3i& lo, const Eigen::Vector3i& res,
                             float background)
    : lo_(lo), res_(res), background_(background), table_(size_t(res.prod()), -1) {}

int32_t* DensityBricks::slot(const Eigen::Vector3i& c) {
    const Eigen::Vector3i r = c - lo_;
    if ((r.array() < 0).any() || (r.array() >= res_.array()).any()) return nullptr;
    return &table_[(size_t(r.x()) * res_.y() + r.y()) * res_.z() + r.z()];
}

void DensityBricks::fill(const Eigen::Vector3i& c, float value) {
    int32_t* s = slot(c);
    if (!s || *s != -1) return;
    *s = -2 - int32_t(constants_.size());
    constants_.push_back(value);
}

}  // namespace shvol
