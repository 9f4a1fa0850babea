// Density lookups in the VDB cloud of media/: through the brick copy (media/density_bricks.h)
// and through an OpenVDB accessor, per point (Medium::sigmaT) and inside ratio tracking along
// rays through the cloud (items: density lookups), with same-run ratios.
#include <benchmark/benchmark.h>

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

}  // namespace
}  // namespace shvol

int main(int argc, char** argv) {
    return shvol::bench::runWithRatios(
        argc, argv, {{"Lookup/1", "Lookup/0"}, {"RatioTracking/1", "RatioTracking/0"}},
        "Same-run ratios (items/s; /1 = bricks, /0 = OpenVDB accessor):");
}
