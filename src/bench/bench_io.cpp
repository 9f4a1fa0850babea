// Density lookups in the VDB cloud of media/: through the brick copy (media/density_bricks.h)
// and through an OpenVDB accessor, per point (Medium::sigmaT) and inside ratio tracking along
// rays through the cloud (items: density lookups); free flights through the sparse plume with
// the majorant grid and with one global majorant, and what a segment and a tentative collision
// cost there; free flights and transmittance through the cloud made optically very thick, with
// and without regular tracking; with same-run ratios.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "ratio_reporter.h"
#include "shvol/core/rng.h"
#include "shvol/io/vdb.h"
#include "shvol/media/tracking.h"

namespace shvol {
namespace {

std::unique_ptr<Medium> cloud(bool bricks) {
    VdbMediumDesc d;
    d.file = std::string(SHVOL_SOURCE_DIR) + "/media/cloud.vdb";
    d.densityScale = 60;  // as media/default.json
    d.bricks = bricks;
    return loadVdbMedium(d);
}

/// Points in the cloud's unit cube (world space of the file), a fixed set.
const std::vector<Vec3>& points() {
    static const std::vector<Vec3> p = [] {
        std::vector<Vec3> v;
        Rng rng(1, 1);
        for (int i = 0; i < 4096; ++i)
            v.push_back(Vec3(rng.uniform(), rng.uniform(), rng.uniform()) - Vec3::Constant(0.5));
        return v;
    }();
    return p;
}

void Lookup(benchmark::State& state) {
    const auto m = cloud(state.range(0) != 0);
    size_t i = 0;
    const std::vector<Vec3>& pts = points();
    for (auto _ : state) benchmark::DoNotOptimize(m->sigmaT(pts[i++ & 4095]));
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(Lookup)->Arg(0)->Arg(1);

void RatioTracking(benchmark::State& state) {
    const auto m = cloud(state.range(0) != 0);
    Rng rng(2, 2);
    TrackingCounters c;
    size_t i = 0;
    const std::vector<Vec3>& pts = points();
    for (auto _ : state) {
        const Vec3 o = pts[i++ & 4095] * 3.0;
        const Ray ray{o, (-o).normalized()};  // towards the centre, through the cloud
        benchmark::DoNotOptimize(
            m->transmittance(ray, NoCollision, TransmittanceEstimator::Ratio, rng, c));
    }
    state.SetItemsProcessed(int64_t(c.densityLookups));
    state.counters["lookups/ray"] = double(c.densityLookups) / double(state.iterations());
    state.counters["segments/ray"] = double(c.segments) / double(state.iterations());
}
BENCHMARK(RatioTracking)->Arg(0)->Arg(1);

/// The i-th of a fixed set of rays from a sphere of radius 2 around the unit cube towards points
/// of the cube.
Ray rayInto(size_t i) {
    const std::vector<Vec3>& pts = points();
    const Vec3 o = pts[i & 4095].normalized() * 2.0, target = pts[(i * 7 + 1) & 4095];
    return Ray{o, (target - o).normalized()};
}

/// Items: rays; counters: density lookups, majorant segments and regular-tracking cells per ray.
void countPerRay(benchmark::State& state, const TrackingCounters& c) {
    const double n = double(state.iterations());
    state.SetItemsProcessed(int64_t(state.iterations()));
    state.counters["lookups/ray"] = double(c.densityLookups) / n;
    state.counters["segments/ray"] = double(c.segments) / n;
    state.counters["cells/ray"] = double(c.exactCells) / n;
}

/// Free flights through the sparse plume of media/plume.json (a column filling < 15% of its
/// box): rays from a sphere around the box towards random points of it (items: rays), with
/// density scale `scale` and majorant cells of `cell` voxels (0: automatic, −1: one global
/// majorant).
void plumeFlights(benchmark::State& state, double scale, int cell) {
    VdbMediumDesc d;
    d.file = std::string(SHVOL_SOURCE_DIR) + "/media/plume.vdb";
    d.densityScale = scale;
    d.majorantGrid = cell >= 0;
    d.majorantCellVoxels = std::max(0, cell);
    const auto m = loadVdbMedium(d);
    Rng rng(3, 3);
    TrackingCounters c;
    size_t i = 0;
    for (auto _ : state)
        benchmark::DoNotOptimize(m->sampleCollision(rayInto(i++), NoCollision, rng, c));
    countPerRay(state, c);
}

/// The plume as media/plume.json has it (density scale 80): /0 one global majorant, /1 the
/// automatic majorant grid, /2 and /8 cells of 2 and 8 voxels.
void PlumeFreeFlight(benchmark::State& state) {
    const int cell = int(state.range(0));
    plumeFlights(state, 80, cell == 0 ? -1 : cell == 1 ? 0 : cell);
}
BENCHMARK(PlumeFreeFlight)->Arg(0)->Arg(1)->Arg(2)->Arg(8);

/// The plume at density scale 1e−9 (no tentative collisions) with cells of 2 and 8 voxels: the
/// difference in time over the difference in segments is the cost of a segment; with it,
/// PlumeFreeFlight/8 − PlumeSegments/8 gives the cost of a tentative collision (the ratio the
/// automatic majorant cell size uses, io/vdb.cpp).
void PlumeSegments(benchmark::State& state) {
    plumeFlights(state, 1e-9, int(state.range(0)));
}
BENCHMARK(PlumeSegments)->Arg(2)->Arg(8);

/// Free flights (/…/0) and ratio-tracked transmittance (/…/1) through the cloud of media/ at
/// density scale 10^range(0), with regular tracking where preferred (range(2) = 1) or tentative
/// collisions only (0): rays from a sphere around the cloud towards random points of its cube.
void ThickCloud(benchmark::State& state) {
    VdbMediumDesc d;
    d.file = std::string(SHVOL_SOURCE_DIR) + "/media/cloud.vdb";
    d.densityScale = std::pow(10.0, double(state.range(0)));
    d.regularTracking = state.range(2) != 0;
    const auto m = loadVdbMedium(d);
    const bool flights = state.range(1) == 0;
    Rng rng(4, 4);
    TrackingCounters c;
    size_t i = 0;
    for (auto _ : state) {
        const Ray ray = rayInto(i++);
        benchmark::DoNotOptimize(
            flights ? m->sampleCollision(ray, NoCollision, rng, c)
                    : m->transmittance(ray, NoCollision, TransmittanceEstimator::Ratio, rng, c));
    }
    countPerRay(state, c);
}
BENCHMARK(ThickCloud)->ArgsProduct({{2, 3, 4, 5, 7}, {0, 1}, {0, 1}});

}  // namespace
}  // namespace shvol

int main(int argc, char** argv) {
    return shvol::bench::runWithRatios(
        argc, argv,
        {{"Lookup/1", "Lookup/0"},
         {"RatioTracking/1", "RatioTracking/0"},
         {"PlumeFreeFlight/1", "PlumeFreeFlight/0"},
         {"ThickCloud/5/0/1", "ThickCloud/5/0/0"},
         {"ThickCloud/7/0/1", "ThickCloud/7/0/0"},
         {"ThickCloud/7/1/1", "ThickCloud/7/1/0"}},
        "Same-run ratios (items/s; Lookup and RatioTracking: /1 bricks, /0 OpenVDB accessor; "
        "PlumeFreeFlight: /1 automatic majorant grid, /0 one global majorant; ThickCloud/s/k: "
        "/1 regular tracking where preferred, /0 tentative collisions only):");
}
