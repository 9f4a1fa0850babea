#include "shvol/render/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>

#include "shvol/core/progress.h"

namespace shvol {

RenderResult render(const Scene& scene, const RenderOptions& options) {
    const Camera& cam = scene.camera;
    const RenderSettings& s = scene.settings;
    const VolumePathIntegrator integrator(scene);
    RenderResult result;
    result.image = Image(cam.width, cam.height);

    constexpr int Tile = 16;
    const int tilesX = (cam.width + Tile - 1) / Tile, tilesY = (cam.height + Tile - 1) / Tile;
    const int threads =
        options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
    tbb::enumerable_thread_specific<PathCounters> counters;
    Progress progress("render", (long long)tilesX * tilesY, options.progress);
    const auto start = std::chrono::steady_clock::now();

    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY, 1), [&](const auto& r) {
            PathCounters& c = counters.local();
            for (int tile = r.begin(); tile < r.end(); ++tile) {
                const int x0 = (tile % tilesX) * Tile, y0 = (tile / tilesX) * Tile;
                for (int y = y0; y < std::min(y0 + Tile, cam.height); ++y)
                    for (int x = x0; x < std::min(x0 + Tile, cam.width); ++x) {
                        const uint64_t pixel = uint64_t(y) * cam.width + x;
                        Spectrum sum = Spectrum::Zero();
                        for (int i = 0; i < s.spp; ++i) {
                            Rng rng = Rng::forSample(s.seed, pixel, i);
                            const Vec2 u = rng.uniform2();
                            const Spectrum L =
                                integrator.Li(cam.generateRay(x + u.x(), y + u.y()), rng, c);
                            if (L.allFinite())
                                sum += L;
                            else
                                ++c.nonFiniteSamples;
                        }
                        result.image.set(x, y, sum / s.spp);
                    }
                progress.advance();
            }
        });
    });
    progress.done();

    RenderStats& st = result.stats;
    st.wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    st.threads = threads;
    st.spp = s.spp;
    st.seed = s.seed;
    for (const PathCounters& c : counters) st.counters.add(c);
    st.effects = integrator.effects().names();
    const Effects& e = integrator.effects();
    if (e.nextEvent) {
        LightSamplingStats& ls = st.lightSampling;
        ls.strategy = lightSamplingName(e.lightSampling);
        ls.mis = misHeuristicName(e.mis);
        ls.setupSeconds = integrator.setupSeconds();
        if (const SkyHierarchy* sky = integrator.sky()) {
            ls.skyResolution = sky->resolution();
            ls.skyBytes = sky->memoryBytes();
            ls.waveletKept = sky->keptDetails();
            ls.waveletDetails = sky->detailCount();
            ls.waveletL2Error = sky->relativeL2Error();
        }
        if (const ProductSampler* ps = integrator.product()) {
            ls.productOrder = ps->order();
            ls.productDepth = ps->productDepth();
        }
    }
    return result;
}

}  // namespace shvol
