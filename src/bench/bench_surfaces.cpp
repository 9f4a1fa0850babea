// Surfaces (issue 7): rays per second against the Embree BVH, closest hit and occlusion, on the
// Cornell box of media/ and on a generated 1M-triangle mesh, with 1 and 2 threads; and paths per
// second of the Cornell box with fog. Rays are made before timing; each thread takes a contiguous
// share of them. Same-run ratios (2 threads / 1 thread) follow the table.
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "ratio_reporter.h"
#include "shvol/core/rng.h"
#include "shvol/io/scene_loader.h"
#include "shvol/render/renderer.h"
#include "shvol/sampling/warp.h"

namespace {

using namespace shvol;

const std::string kMedia = std::string(SHVOL_SOURCE_DIR) + "/media/";

/// A latitude-longitude sphere of 2·nTheta·nPhi triangles (near enough).
TriangleMesh sphereMesh(int nTheta, int nPhi) {
    TriangleMesh m;
    for (int i = 0; i <= nTheta; ++i)
        for (int j = 0; j < nPhi; ++j)
            m.p.push_back(
                sphericalDirection(std::cos(Pi * (i + 0.5) / (nTheta + 1)), TwoPi * j / nPhi));
    for (int i = 0; i < nTheta; ++i)
        for (int j = 0; j < nPhi; ++j) {
            const uint32_t a = i * nPhi + j, b = i * nPhi + (j + 1) % nPhi;
            m.indices.insert(m.indices.end(), {a, a + nPhi, b + nPhi, a, b + nPhi, b});
        }
    return m;
}

struct Workload {
    std::unique_ptr<const SurfaceScene> scene;
    std::vector<Ray> rays;
    std::vector<double> tMax;  ///< occlusion: the segment lengths
};

/// Rays between random points of the Cornell box's interior (closest hit: from the first point in
/// a uniform direction; occlusion: the segment to the second point).
const Workload& cornell() {
    static const Workload w = [] {
        Workload w;
        Scene s = loadScene(kMedia + "cornell.json");
        w.scene = std::move(s.surfaces);
        Rng rng(1, 0);
        for (int i = 0; i < 1 << 20; ++i) {
            const Vec3 a(556 * rng.uniform(), 548 * rng.uniform(), 559 * rng.uniform());
            const Vec3 b(556 * rng.uniform(), 548 * rng.uniform(), 559 * rng.uniform());
            w.rays.push_back(Ray{a, sampleUniformSphere(rng.uniform2())});
            w.tMax.push_back((b - a).norm());
            w.rays.push_back(Ray{a, (b - a).normalized()});
        }
        return w;
    }();
    return w;
}

/// A 1M-triangle sphere of radius 1, shot at from a sphere of radius 3 towards random points
/// within radius 1.2 (most rays hit; occlusion segments end at the target point).
const Workload& bigMesh() {
    static const Workload w = [] {
        Workload w;
        Surface s;
        s.kind = Surface::Kind::Mesh;
        s.mesh = sphereMesh(500, 1000);
        std::vector<Surface> v;
        v.push_back(std::move(s));
        w.scene = std::make_unique<const SurfaceScene>(std::move(v));
        Rng rng(2, 0);
        for (int i = 0; i < 1 << 20; ++i) {
            const Vec3 o = 3 * sampleUniformSphere(rng.uniform2());
            const Vec3 t = 1.2 * std::cbrt(rng.uniform()) * sampleUniformSphere(rng.uniform2());
            w.rays.push_back(Ray{o, (t - o).normalized()});
            w.tMax.push_back((t - o).norm());
            w.rays.push_back(Ray{o, (t - o).normalized()});
        }
        return w;
    }();
    return w;
}

/// Rays of w (even indices: closest hit; odd: occlusion) traced by `threads` threads.
void trace(benchmark::State& state, const Workload& w, bool occlusion) {
    const int threads = int(state.range(0));
    tbb::task_arena arena(threads);
    const size_t n = w.tMax.size();
    size_t hits = 0;
    for (auto _ : state) {
        std::vector<size_t> perThread(threads, 0);
        arena.execute([&] {
            tbb::parallel_for(0, threads, [&](int t) {
                size_t h = 0;
                SurfaceHit hit;
                for (size_t i = n * t / threads; i < n * (t + 1) / threads; ++i)
                    h += occlusion ? w.scene->occluded(w.rays[2 * i + 1], w.tMax[i])
                                   : w.scene->intersect(w.rays[2 * i], NoHit, &hit);
                perThread[t] = h;
            });
        });
        for (size_t h : perThread) hits += h;
    }
    benchmark::DoNotOptimize(hits);
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(n));
    state.counters["hit_fraction"] = double(hits) / (double(state.iterations()) * n);
}

void CornellClosestHit(benchmark::State& s) {
    trace(s, cornell(), false);
}
void CornellOcclusion(benchmark::State& s) {
    trace(s, cornell(), true);
}
void MeshClosestHit(benchmark::State& s) {
    trace(s, bigMesh(), false);
}
void MeshOcclusion(benchmark::State& s) {
    trace(s, bigMesh(), true);
}
BENCHMARK(CornellClosestHit)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(CornellOcclusion)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(MeshClosestHit)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(MeshOcclusion)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

/// Paths per second of the fog Cornell box (128², 4 spp per iteration).
void CornellFogPaths(benchmark::State& state) {
    static const Scene scene =
        loadScene(kMedia + "cornell_fog.json", {"camera.resolution=[128, 128]", "render.spp=4"});
    RenderOptions opt;
    opt.threads = int(state.range(0));
    uint64_t paths = 0;
    for (auto _ : state) paths += render(scene, opt).stats.counters.paths;
    state.SetItemsProcessed(int64_t(paths));
}
BENCHMARK(CornellFogPaths)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
    return shvol::bench::runWithRatios(
        argc, argv,
        {{"CornellClosestHit/2/real_time", "CornellClosestHit/1/real_time"},
         {"CornellOcclusion/2/real_time", "CornellOcclusion/1/real_time"},
         {"MeshClosestHit/2/real_time", "MeshClosestHit/1/real_time"},
         {"MeshOcclusion/2/real_time", "MeshOcclusion/1/real_time"},
         {"CornellFogPaths/2/real_time", "CornellFogPaths/1/real_time"}},
        "Same-run ratios, 2 threads / 1 thread (items/s):");
}
