// The only translation unit that includes OpenVDB (6–20 s to compile).
#include "shvol/io/vdb.h"

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <filesystem>
#include <mutex>
#include <sstream>

#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"
#include "shvol/media/majorant_grid.h"

namespace shvol {

namespace {

void initOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

class VdbMedium final : public Medium {
  public:
    VdbMedium(const VdbMediumDesc& d, openvdb::FloatGrid::ConstPtr grid,
              const Eigen::Affine3d& worldToIndex, MajorantGrid majorants)
        : Medium(d.albedo, d.phase),
          grid_(std::move(grid)),
          worldToIndex_(worldToIndex),
          scale_(d.densityScale),
          majorants_(std::move(majorants)),
          desc_("vdb " + d.file + ":" + d.grid) {}

  private:
    // Not registered with the tree: cheap to make per ray, private to the calling thread.
    using Accessor = openvdb::tree::ValueAccessor<const openvdb::FloatTree, false>;

    auto segments(const Vec3& o, const Vec3& d, double tMax) const {
        // The majorant is inflated by 1e-6 relative so that float rounding in the trilinear
        // interpolation can never exceed it.
        const double k = scale_ * (1 + 1e-6);
        return [this, o, d, tMax, k](auto&& visit) {
            majorants_.traverse(o, d, 0, tMax, [&](double t0, double t1, double m) {
                return visit(t0, t1, k * m);
            });
        };
    }
    auto sigma(Accessor& acc, const Vec3& o, const Vec3& d) const {
        return [this, &acc, o, d](double t) {
            const Vec3 p = o + t * d;
            return scale_ * double(openvdb::tools::BoxSampler::sample(
                                acc, openvdb::Vec3R(p.x(), p.y(), p.z())));
        };
    }

  public:
    double sampleCollision(const Ray& ray, double tMax, Rng& rng,
                           TrackingCounters& c) const override {
        Accessor acc(grid_->tree());
        const Vec3 o = worldToIndex_ * ray.o, d = worldToIndex_.linear() * ray.d;
        return deltaTrack(segments(o, d, tMax), sigma(acc, o, d), rng, c);
    }

    double transmittance(const Ray& ray, double tMax, TransmittanceEstimator est, Rng& rng,
                         TrackingCounters& c) const override {
        Accessor acc(grid_->tree());
        const Vec3 o = worldToIndex_ * ray.o, d = worldToIndex_.linear() * ray.d;
        return est == TransmittanceEstimator::Ratio
                   ? ratioTrack(segments(o, d, tMax), sigma(acc, o, d), rng, c)
                   : deltaTrackTransmittance(segments(o, d, tMax), sigma(acc, o, d), rng, c);
    }

    double sigmaT(const Vec3& p) const override {
        Accessor acc(grid_->tree());
        const Vec3 q = worldToIndex_ * p;
        return scale_ *
               openvdb::tools::BoxSampler::sample(acc, openvdb::Vec3R(q.x(), q.y(), q.z()));
    }

    double sigmaMajorant(const Vec3& p) const override {
        return scale_ * (1 + 1e-6) * majorants_.at(worldToIndex_ * p);
    }

    std::string describe() const override { return desc_; }

  private:
    openvdb::FloatGrid::ConstPtr grid_;
    Eigen::Affine3d worldToIndex_;
    double scale_;
    MajorantGrid majorants_;
    std::string desc_;
};

std::string ijkString(const openvdb::Coord& c) {
    std::ostringstream s;
    s << "(" << c.x() << ", " << c.y() << ", " << c.z() << ")";
    return s.str();
}

}  // namespace

std::unique_ptr<Medium> loadVdbMedium(const VdbMediumDesc& desc) {
    initOpenVdb();
    const std::string& path = desc.file;
    const std::string where = "grid '" + desc.grid + "'";
    if (!std::filesystem::exists(path)) fail(path, "", "file not found");
    openvdb::GridBase::Ptr base;
    try {
        openvdb::io::File file(path);
        file.open(false);  // no delayed loading: the whole grid is read now
        if (!file.hasGrid(desc.grid)) {
            std::string names;
            for (auto it = file.beginName(); it != file.endName(); ++it)
                names += (names.empty() ? "" : ", ") + it.gridName();
            fail(path, where, "no such grid; the file has: " + (names.empty() ? "(none)" : names));
        }
        base = file.readGrid(desc.grid);
        file.close();
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        fail(path, "", std::string("not a readable OpenVDB file (") + e.what() + ")");
    }
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (!grid) fail(path, where, "has value type " + base->valueType() + ", expected float");
    if (!grid->transform().isLinear()) fail(path, where, "non-linear transforms are not supported");
    if (grid->background() != 0.f)
        fail(path, where, "background value must be 0, is " + std::to_string(grid->background()));

    // Index → grid world (OpenVDB multiplies row vectors: w = [i j k 1]·M), then → scene.
    const openvdb::Mat4d m = grid->transform().baseMap()->getAffineMap()->getMat4();
    Eigen::Matrix4d a;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) a(r, c) = m(c, r);
    const Eigen::Affine3d indexToWorld = desc.toWorld * Eigen::Affine3d(a);

    // Pass 1: validate every stored value and find the bounds of non-zero density.
    const openvdb::FloatTree& tree = grid->tree();
    openvdb::CoordBBox bounds;
    for (auto it = tree.cbeginValueAll(); it; ++it) {
        const float v = *it;
        if (!std::isfinite(v) || v < 0)
            fail(path, where,
                 std::string(std::isfinite(v) ? "negative" : "NaN or infinite") + " density " +
                     std::to_string(v) + " at voxel " + ijkString(it.getCoord()));
        if (v > 0) bounds.expand(it.getBoundingBox());
    }
    MajorantGrid majorants;
    if (!bounds.empty()) {
        // Trilinear lookups reach one voxel beyond a stored value.
        const Vec3 lo(bounds.min().x() - 1, bounds.min().y() - 1, bounds.min().z() - 1);
        const Vec3 hi(bounds.max().x() + 1, bounds.max().y() + 1, bounds.max().z() + 1);
        Eigen::Vector3i res(1, 1, 1);
        if (desc.majorantGrid)
            res = ((hi - lo) / std::max(1, desc.majorantCellVoxels)).array().ceil().cast<int>();
        majorants = MajorantGrid(lo, hi, res);
        for (auto it = tree.cbeginValueAll(); it; ++it) {
            if (*it <= 0) continue;
            const openvdb::CoordBBox b = it.getBoundingBox();
            majorants.expand(Vec3(b.min().x() - 1, b.min().y() - 1, b.min().z() - 1),
                             Vec3(b.max().x() + 1, b.max().y() + 1, b.max().z() + 1), *it);
        }
    }
    return std::make_unique<VdbMedium>(desc, grid, indexToWorld.inverse(), std::move(majorants));
}

size_t writeVdb(const std::string& path, const std::vector<VdbGridSpec>& specs) {
    initOpenVdb();
    openvdb::GridPtrVec grids;
    size_t active = 0;
    for (const VdbGridSpec& s : specs) {
        const double h = 1.0 / s.resolution;
        auto xform = openvdb::math::Transform::createLinearTransform(h);
        xform->postTranslate(openvdb::Vec3d(-0.5 + 0.5 * h));
        auto at = [&](int i, int j, int k) {
            return s.density(Vec3((i + 0.5) * h - 0.5, (j + 0.5) * h - 0.5, (k + 0.5) * h - 0.5));
        };
        auto fill = [&](auto grid, auto make) {
            auto acc = grid->getAccessor();
            for (int k = 0; k < s.resolution; ++k)
                for (int j = 0; j < s.resolution; ++j)
                    for (int i = 0; i < s.resolution; ++i) {
                        const float v = at(i, j, k);
                        if (v != 0.f || std::isnan(v))
                            acc.setValue(openvdb::Coord(i, j, k), make(v));
                    }
            active += grid->activeVoxelCount();
            grid->setName(s.name);
            grid->setTransform(xform);
            grid->setGridClass(openvdb::GRID_FOG_VOLUME);
            grids.push_back(grid);
        };
        if (s.type == VdbGridSpec::Type::Float)
            fill(openvdb::FloatGrid::create(0.f), [](float v) { return v; });
        else
            fill(openvdb::Vec3SGrid::create(), [](float v) { return openvdb::Vec3s(v); });
    }
    writeAtomically(path, [&](const std::string& tmp) {
        try {
            openvdb::io::File file(tmp);
            file.write(grids);
            file.close();
        } catch (const std::exception& e) {
            fail(path, "", std::string("cannot write VDB (") + e.what() + ")");
        }
    });
    return active;
}

}  // namespace shvol
