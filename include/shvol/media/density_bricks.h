#pragma once
/// \file A copy of a VDB density grid laid out for the tracking loop: 8³-voxel bricks, one per
/// VDB leaf position that can matter, each stored with a one-voxel apron on its +x, +y and +z
/// sides (9³ floats), so that a trilinear lookup reads one contiguous brick; a dense table of
/// brick indices over the bricks' bounding box finds it in one step. OpenVDB stays the file
/// format and the source of truth: the bricks are filled from the grid at load (io/vdb.cpp), and
/// a lookup returns exactly what openvdb::tools::BoxSampler::sample returns (the same floor,
/// weights and order of interpolation, z then y then x, in float with double weights), so
/// images do not change. Positions are in the grid's index space, voxel centres at integers.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "shvol/core/math.h"

namespace shvol {

class DensityBricks {
  public:
    static constexpr int kBrick = 8;          ///< voxels per brick side (a VDB leaf)
    static constexpr int kSide = kBrick + 1;  ///< stored per side, with the apron
    static constexpr int kVoxels = kSide * kSide * kSide;

    DensityBricks() = default;
    /// An empty table over brick coordinates [lo, lo + res) (brick c covers voxels 8c … 8c + 7)
    /// whose every lookup gives `background`.
    DensityBricks(const Eigen::Vector3i& lo, const Eigen::Vector3i& res, float background);

    /// Room for `bricks` bricks in all: adding them then moves no stored brick.
    void reserve(size_t bricks) { values_.reserve(bricks * kVoxels); }
    /// Adds the brick at brick coordinate c, filled by voxel(x, y, z) for the voxels
    /// 8c … 8c + 8 of each axis (the brick and its apron).
    template <typename Voxel>
    void add(const Eigen::Vector3i& c, Voxel&& voxel);

    /// Marks the brick position c as holding `value` in all its voxels and its apron (inside a
    /// tile of the VDB): no brick is stored for it. A brick added there wins.
    void fill(const Eigen::Vector3i& c, float value);

    /// The trilinear interpolation of the voxels around p (BoxSampler's result).
    float sample(const Vec3& p) const;
    /// The voxels (x + a, y + b, z + k), a, b, k ∈ {0, 1}, as v[4a + 2b + k]: the corners of the
    /// unit cell whose trilinear interpolation sample() takes at points of [x, x + 1)³.
    void corners(int x, int y, int z, float v[8]) const;

    size_t brickCount() const { return values_.size() / kVoxels; }
    size_t constantCount() const { return constants_.size(); }
    size_t memoryBytes() const {
        return (values_.size() + constants_.size()) * sizeof(float) +
               table_.size() * sizeof(int32_t);
    }

  private:
    int32_t* slot(const Eigen::Vector3i& c);
    /// The table entry of the brick holding voxel (ix, iy, iz): as table_, −1 outside the table.
    int32_t brick(int ix, int iy, int iz) const;
    /// The voxel (ix, iy, iz) in its stored brick b, whose apron holds the +1 neighbours.
    const float* voxel(int32_t b, int ix, int iy, int iz) const;
    Eigen::Vector3i lo_{0, 0, 0}, res_{0, 0, 0};
    float background_ = 0;
    /// Per table cell: a brick index (≥ 0), −1 for the background, or −2 − k for constants_[k].
    std::vector<int32_t> table_;
    std::vector<float> values_;     ///< kVoxels per brick, x slowest, z fastest
    std::vector<float> constants_;  ///< values of the constant positions
};

template <typename Voxel>
void DensityBricks::add(const Eigen::Vector3i& c, Voxel&& voxel) {
    int32_t* s = slot(c);
    if (!s || *s >= 0) return;  // outside the table, or there already
    *s = int32_t(brickCount());
    const Eigen::Vector3i v0 = c * kBrick;
    for (int i = 0; i < kSide; ++i)
        for (int j = 0; j < kSide; ++j)
            for (int k = 0; k < kSide; ++k)
                values_.push_back(float(voxel(v0.x() + i, v0.y() + j, v0.z() + k)));
}

inline __attribute__((always_inline)) int32_t DensityBricks::brick(int ix, int iy, int iz) const {
    // Brick coordinates by arithmetic shift (floor division by 8 for negative voxels too).
    const int bx = (ix >> 3) - lo_.x(), by = (iy >> 3) - lo_.y(), bz = (iz >> 3) - lo_.z();
    if (unsigned(bx) >= unsigned(res_.x()) || unsigned(by) >= unsigned(res_.y()) ||
        unsigned(bz) >= unsigned(res_.z()))
        return -1;
    return table_[(size_t(bx) * res_.y() + by) * res_.z() + bz];
}

inline const float* DensityBricks::voxel(int32_t b, int ix, int iy, int iz) const {
    return values_.data() + size_t(b) * kVoxels + ((ix & 7) * kSide + (iy & 7)) * kSide + (iz & 7);
}

inline void DensityBricks::corners(int x, int y, int z, float v[8]) const {
    const int32_t b = brick(x, y, z);
    if (b < 0) {
        std::fill(v, v + 8, b == -1 ? background_ : constants_[size_t(-2 - b)]);
        return;
    }
    const float* p = voxel(b, x, y, z);
    constexpr int X = kSide * kSide, Y = kSide;
    for (int i = 0; i < 8; ++i) v[i] = p[(i >> 2) * X + ((i >> 1) & 1) * Y + (i & 1)];
}

inline __attribute__((always_inline)) float DensityBricks::sample(const Vec3& p) const {
    const int ix = floorToInt(p.x()), iy = floorToInt(p.y()), iz = floorToInt(p.z());
    const int32_t b = brick(ix, iy, iz);
    if (b < 0) return b == -1 ? background_ : constants_[size_t(-2 - b)];
    const float* v = voxel(b, ix, iy, iz);
    const double u = p.x() - ix, w = p.y() - iy, t = p.z() - iz;
    // BoxSampler::trilinearInterpolation: a + float((b − a)·weight), innermost along z.
    auto lerp = [](float a, float b, double weight) { return a + float((b - a) * weight); };
    constexpr int X = kSide * kSide, Y = kSide;
    return lerp(lerp(lerp(v[0], v[1], t), lerp(v[Y], v[Y + 1], t), w),
                lerp(lerp(v[X], v[X + 1], t), lerp(v[X + Y], v[X + Y + 1], t), w), u);
}

}  // namespace shvol
