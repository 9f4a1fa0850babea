// The brick copy of a VDB grid (media/density_bricks.h, built in io/vdb.cpp) against OpenVDB's
// own trilinear lookup, the slow reference it replaces in the tracking loop.
#include "shvol/media/density_bricks.h"

#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <set>

#include "shvol/core/rng.h"
#include "shvol/io/scene_loader.h"
#include "shvol/io/vdb.h"
#include "shvol/render/renderer.h"

namespace shvol {
namespace {

/// A grid with leaves on both sides of the origin, a lone voxel, leaves touching each other and
/// a 128³ tile, written to a file; returns its path.
std::string writeAwkwardGrid(const std::string& name) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.f);
    auto acc = grid->getAccessor();
    Rng rng(3, 1);
    for (int x = -20; x < 12; ++x)
        for (int y = -9; y < 7; ++y)
            for (int z = -3; z < 30; ++z)
                if (rng.uniform() < 0.7)
                    acc.setValue(openvdb::Coord(x, y, z), float(rng.uniform()));
    acc.setValue(openvdb::Coord(-100, 40, 7), 2.5f);
    grid->tree().addTile(2, openvdb::Coord(128, 0, 0), 0.75f, true);  // a level-2 tile, 128³
    grid->setName("density");
    // (one file per test: ctest runs them side by side, and one rewrote the other's file while it
    // was read)
    const std::string path = testing::TempDir() + "/shvol_bricks_" + name + ".vdb";
    openvdb::io::File file(path);
    file.write({grid});
    file.close();
    return path;
}

/// σ_t at `n` points of the index-space box [lo, hi]: random ones, and lattice and half-lattice
/// points (brick and apron boundaries).
void expectSameDensity(const Medium& a, const Medium& b, const Vec3& lo, const Vec3& hi, int n) {
    Rng rng(11, 2);
    for (int i = 0; i < n; ++i) {
        Vec3 p = lo + (hi - lo).cwiseProduct(Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
        if (i % 3 == 1) p = p.array().round();
        if (i % 3 == 2) p = (2 * p).array().round() / 2;
        ASSERT_EQ(a.sigmaT(p), b.sigmaT(p)) << p.transpose();
    }
}

}  // namespace

// Bricks give exactly OpenVDB's trilinear values everywhere: at random points, on the voxel
// lattice and halfway between, across brick boundaries, at negative coordinates, in a tile and
// outside all data.
TEST(DensityBricks, SameValuesAsOpenVdb) {
    VdbMediumDesc d;
    d.file = writeAwkwardGrid("values");  // index space = world space (identity transform)
    d.densityScale = 3;
    const auto bricks = loadVdbMedium(d);
    d.bricks = false;
    const auto openvdb = loadVdbMedium(d);
    // The comparison means something only if the bricks were built (no silent fallback).
    EXPECT_NE(bricks->describe().find("brick lookups"), std::string::npos) << bricks->describe();
    EXPECT_NE(openvdb->describe().find("OpenVDB lookups"), std::string::npos);
    expectSameDensity(*bricks, *openvdb, Vec3(-30, -15, -10), Vec3(20, 15, 40), 300000);
    expectSameDensity(*bricks, *openvdb, Vec3(-110, 30, 0), Vec3(-90, 50, 15), 20000);
    expectSameDensity(*bricks, *openvdb, Vec3(120, -8, -8), Vec3(264, 136, 136), 100000);
    EXPECT_EQ(bricks->sigmaT(Vec3(200, 60, 60)), 3 * 0.75);
    EXPECT_EQ(bricks->sigmaT(Vec3(-100, 40, 7)), 3 * 2.5);
}

// Regular tracking reads whole voxel cells (DensityBricks::corners, or OpenVDB's accessor): on the
// awkward grid, at a density scale where it takes most cells, free flights and both transmittance
// estimates along rays through negative coordinates, brick boundaries, the lone voxel and the
// 128³ tile are the same, number for number, through bricks and through OpenVDB (helper 92: only
// the single-voxel grid compared corners() with OpenVDB).
TEST(DensityBricks, RegularTrackingReadsTheSameCells) {
    VdbMediumDesc d;
    d.file = writeAwkwardGrid("regular");
    d.densityScale = 40;
    const auto bricks = loadVdbMedium(d);
    d.bricks = false;
    const auto openvdb = loadVdbMedium(d);
    Rng rays(23, 4);
    TrackingCounters cb, co;
    // (box corners, rays): the cloud of leaves about the origin, the lone voxel, the tile.
    const std::vector<std::pair<Vec3, Vec3>> boxes = {{Vec3(-21, -10, -4), Vec3(13, 8, 31)},
                                                      {Vec3(-101, 39, 6), Vec3(-99, 41, 8)},
                                                      {Vec3(126, -2, -2), Vec3(258, 130, 130)}};
    for (const auto& [lo, hi] : boxes)
        for (int i = 0; i < 3000; ++i) {
            const Vec3 to =
                lo + (hi - lo).cwiseProduct(Vec3(rays.uniform(), rays.uniform(), rays.uniform()));
            const Vec3 from = to + 1.5 * (hi - lo).norm() * sampleUniformSphere(rays.uniform2());
            const Ray r{from, (to - from).normalized()};
            const double tMax = 3 * (hi - lo).norm();
            Rng a(9, uint64_t(i)), b(9, uint64_t(i));
            ASSERT_EQ(bricks->sampleCollision(r, tMax, a, cb),
                      openvdb->sampleCollision(r, tMax, b, co))
                << "ray " << i << " towards " << to.transpose();
            for (const auto est : {TransmittanceEstimator::Ratio, TransmittanceEstimator::Delta})
                ASSERT_EQ(bricks->transmittance(r, tMax, est, a, cb),
                          openvdb->transmittance(r, tMax, est, b, co))
                    << "ray " << i << " towards " << to.transpose();
        }
    EXPECT_EQ(cb.exactCells, co.exactCells);
    EXPECT_GT(cb.exactCells, 10000u);  // regular tracking was used
}

// The default cloud renders the same image, with the same number of density lookups, through
// bricks and through OpenVDB.
TEST(DensityBricks, RendersTheSameImage) {
    const std::string scene = std::string(SHVOL_SOURCE_DIR) + "/media/default.json";
    const std::vector<std::string> sets = {"camera.resolution=[40,30]", "render.spp=4",
                                           "environment={\"type\": \"constant\", \"radiance\": 1}"};
    const Scene a = loadScene(scene, sets);
    std::vector<std::string> viaOpenVdb = sets;
    viaOpenVdb.push_back("media[0].lookup=\"openvdb\"");
    const Scene b = loadScene(scene, viaOpenVdb);
    EXPECT_NE(a.media[0]->describe().find("brick lookups"), std::string::npos);
    EXPECT_NE(b.media[0]->describe().find("OpenVDB lookups"), std::string::npos);
    const RenderResult ra = render(a, RenderOptions{}), rb = render(b, RenderOptions{});
    EXPECT_EQ(ra.image.rgb, rb.image.rgb);
    EXPECT_EQ(ra.stats.counters.tracking.densityLookups, rb.stats.counters.tracking.densityLookups);
    EXPECT_GT(ra.stats.counters.tracking.densityLookups, 10000u);
}

// Where neighbouring tiles hold one value, the brick positions between them are constants: a
// brick is stored only where a window (brick and apron) holds more than one value, counted here
// by reading every window's 9³ voxels through OpenVDB. The grid: a 6 × 6 × 6 block of 8³ tiles
// of 0.5 beside a 2 × 6 × 6 block of 0.25, and above them a leaf of varying voxels. The code
// before helper 138's finding stored a brick at every tile's shell position (445 here, where
// 295 are needed).
TEST(DensityBricks, TilesOfOneValueShareNoBricks) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.f);
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 6; ++y)
            for (int z = 0; z < 6; ++z)
                grid->tree().addTile(1, openvdb::Coord(8 * x, 8 * y, 8 * z), x < 6 ? 0.5f : 0.25f,
                                     true);
    auto acc = grid->getAccessor();
    for (int i = 0; i < 512; ++i)
        acc.setValue(openvdb::Coord(16 + i / 64, 16 + i / 8 % 8, 48 + i % 8), 1.f + i % 7);
    grid->setName("density");
    VdbMediumDesc d;
    d.file = testing::TempDir() + "/shvol_bricks_tiles.vdb";
    openvdb::io::File file(d.file);
    file.write({grid});
    file.close();
    size_t needed = 0;
    for (int x = -1; x <= 8; ++x)
        for (int y = -1; y <= 6; ++y)
            for (int z = -1; z <= 6; ++z) {
                std::set<float> values;
                for (int i = 0; i < 729; ++i)
                    values.insert(acc.getValue(
                        openvdb::Coord(8 * x + i / 81, 8 * y + i / 9 % 9, 8 * z + i % 9)));
                needed += values.size() > 1;
            }
    const auto bricks = loadVdbMedium(d);
    d.bricks = false;
    const auto openvdb = loadVdbMedium(d);
    EXPECT_NE(bricks->describe().find("(" + std::to_string(needed) + " bricks"), std::string::npos)
        << needed << " needed: " << bricks->describe();
    expectSameDensity(*bricks, *openvdb, Vec3(-10, -10, -10), Vec3(74, 58, 66), 200000);
}

// A brick table with no bricks is the background everywhere; a brick added twice is kept once;
// constant positions (tile interiors) need no brick.
TEST(DensityBricks, EmptyTableAndRepeatedBricks) {
    DensityBricks b(Eigen::Vector3i(-1, -1, -1), Eigen::Vector3i(2, 2, 2), 0.f);
    EXPECT_EQ(b.sample(Vec3(0.5, -3.5, 2)), 0.f);
    b.add(Eigen::Vector3i(0, 0, 0), [](int x, int y, int z) { return x + 10 * y + 100 * z; });
    b.add(Eigen::Vector3i(0, 0, 0), [](int, int, int) { return -1; });
    b.add(Eigen::Vector3i(5, 0, 0), [](int, int, int) { return -1; });  // outside: ignored
    EXPECT_EQ(b.brickCount(), 1u);
    EXPECT_FLOAT_EQ(b.sample(Vec3(1.5, 2.25, 3)), 1.5f + 22.5f + 300.f);
    EXPECT_FLOAT_EQ(b.sample(Vec3(7.5, 7.75, 7.25)), 810.f);  // reaches into the apron (x = 8)
    EXPECT_EQ(b.sample(Vec3(8, 8, 8)), 0.f);                  // brick (1, 1, 1): none
    EXPECT_EQ(b.sample(Vec3(-0.5, 1, 1)), 0.f);               // brick (−1, 0, 0): none
    // A constant position (inside a tile) holds its value everywhere, a brick added there wins,
    // and a constant does not replace a brick.
    b.fill(Eigen::Vector3i(-1, 0, 0), 0.25f);
    EXPECT_EQ(b.sample(Vec3(-0.5, 1, 1)), 0.25f);
    b.fill(Eigen::Vector3i(0, 0, 0), 9.f);
    EXPECT_FLOAT_EQ(b.sample(Vec3(1.5, 2.25, 3)), 324.f);
    b.fill(Eigen::Vector3i(0, -1, 0), 0.5f);
    b.add(Eigen::Vector3i(0, -1, 0), [](int, int, int) { return 2; });
    EXPECT_EQ(b.sample(Vec3(3, -3, 3)), 2.f);
    EXPECT_EQ(b.brickCount(), 2u);
    EXPECT_EQ(b.constantCount(), 2u);
}

}  // namespace shvol
