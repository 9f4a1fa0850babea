#pragma once
/// \file OpenVDB media. This header keeps OpenVDB out of every translation unit but src/io/vdb.cpp.
#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "shvol/media/medium.h"

namespace shvol {

struct VdbMediumDesc {
    std::string file;
    std::string grid = "density";
    double densityScale = 1;  ///< σ_t(x) = densityScale · density(x), per scene unit
    Spectrum albedo = Spectrum::Ones();
    PhaseFunction phase = PhaseFunction(IsotropicPhase());
    Eigen::Affine3d toWorld = Eigen::Affine3d::Identity();  ///< the grid's world space → scene
    bool majorantGrid = true;  ///< false: one global majorant for the whole grid (for benchmarks)
    /// Majorant cell edge in voxels; 0: chosen at load among 1, 2, 4, … voxels (up to one cell
    /// over the grid) by the expected tracking cost (MajorantGrid::trackingCost).
    int majorantCellVoxels = 0;
    /// Density lookups from a brick copy of the grid (media/density_bricks.h); false: through an
    /// OpenVDB value accessor (the reference, for benchmarks). Both give the same values.
    bool bricks = true;
    /// Decomposition and residual ratio tracking with a per-cell lower bound of the density
    /// (media/tracking.h); false: plain delta and ratio tracking (for benchmarks).
    bool decomposition = true;
    /// Regular tracking (media/trilinear_depth.h) across the majorant segments where it is the
    /// cheaper way; false: tentative collisions everywhere (for benchmarks and tests).
    bool regularTracking = true;
};

/// Loads a FloatGrid and builds its majorant grid (trilinear density lookups). Errors name the
/// file and the grid: missing or corrupt file, missing grid, wrong value type, non-linear
/// transform, non-zero background, negative or NaN density (with the voxel).
std::unique_ptr<Medium> loadVdbMedium(const VdbMediumDesc& desc);

/// A grid to write: values are sampled at voxel centres of a res³ lattice that fills the cube
/// [−½, ½]³ of the grid's world space (voxel size 1/res). Zero values are left inactive.
struct VdbGridSpec {
    std::string name = "density";
    enum class Type { Float, Vec3 } type = Type::Float;  ///< Vec3 exists to test type errors
    int resolution = 64;
    std::function<float(const Vec3& p)> density;  ///< p ∈ [−½, ½]³
};

/// What writeVdb made of a grid, before writing it.
struct VdbGridSummary {
    size_t activeVoxels = 0;
    Eigen::Vector3i lo{0, 0, 0},
        hi{-1, -1, -1};  ///< index box of the active voxels (lo > hi: none)
};

/// Writes grids to a .vdb file (atomically). Returns the number of active voxels written. The
/// voxels are evaluated once each, in parallel (on the threads of the calling task arena), in
/// slabs one leaf (8 voxels) deep along z, whose trees are merged in slab order: the file does not
/// depend on the thread count, so `density` must be safe to call from several threads.
/// `beforeWrite` (optional) sees every grid's summary once all are made and before the file is
/// opened; it refuses by throwing. `progress`: a progress bar on stderr when it is a terminal.
size_t writeVdb(const std::string& path, const std::vector<VdbGridSpec>& grids,
                const std::function<void(const std::vector<VdbGridSummary>&)>& beforeWrite = {},
                bool progress = false);

}  // namespace shvol
