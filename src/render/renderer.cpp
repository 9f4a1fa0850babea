#include "shvol/render/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "shvol/core/deadline.h"
#include "shvol/core/error.h"
#include "shvol/core/progress.h"
#include "shvol/core/thread_arena.h"

namespace shvol {

const char* renderStopName(RenderStop s) {
    switch (s) {
        case RenderStop::Cancelled:
            return "cancelled";
        case RenderStop::TimeLimit:
            return "time-limit";
        default:
            return "completed";
    }
}

namespace {

/// The end of the pass after one that ended at `have` samples per pixel: the next power of two
/// (passes double), spp or the next requested stop, whichever comes first, and at most `cap`
/// (≥ 1) samples past `have`.
uint32_t nextPassEnd(uint32_t have, uint32_t spp, const std::vector<uint32_t>& stops,
                     uint64_t cap) {
    uint64_t end = 1;
    while (end <= have) end *= 2;
    end = std::min<uint64_t>(end, spp);
    if (end - have > cap) end = have + cap;
    for (const uint32_t stop : stops)
        if (stop > have) end = std::min<uint64_t>(end, stop);
    return uint32_t(end);
}

/// What the integrator decided and built: the effects and the light sampler.
void describeIntegrator(const VolumePathIntegrator& integrator, RenderStats& st) {
    st.effects = integrator.effects().names();
    st.rouletteThreshold = integrator.effects().rouletteThreshold;
    if (const RadianceCache* cache = integrator.radianceCache()) {
        const VolumePathIntegrator::CacheBuild& b = integrator.cacheBuild();
        st.radianceCache = {true,
                            cache->size(),
                            cache->memoryBytes(),
                            b.tableBytes,
                            b.tableSeconds,
                            b.fillSeconds,
                            b.tableErrors,
                            b.uncached,
                            b.counters.paths,
                            b.counters.truncatedPaths,
                            b.counters.nonFiniteSamples,
                            b.counters.invalid};
        if (!b.recordErrors.empty()) {
            std::vector<float> e = b.recordErrors;
            std::sort(e.begin(), e.end());
            // Nearest rank: the smallest value that q of the records are at or below.
            const auto rank = [&](double q) {
                return double(e[size_t(std::ceil(q * double(e.size()))) - 1]);
            };
            st.radianceCache.recordErrorMedian = rank(0.5);
            st.radianceCache.recordErrorP90 = rank(0.9);
            st.radianceCache.recordErrorMax = e.back();
        }
    }
    const Effects& e = integrator.effects();
    if (!e.nextEvent) return;
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
        ls.waveletSecondMoment = sky->lightSecondMoment();
    }
    if (const ProductSampler* ps = integrator.product()) {
        ls.productOrder = ps->order();
        ls.productDepth = ps->productDepth();
    }
}

}  // namespace

uint64_t passSampleCap(double maxPassSeconds, double seconds, uint64_t samples, uint64_t pixels) {
    if (!(seconds > 0) || pixels == 0) return std::numeric_limits<uint64_t>::max();
    return uint64_t(
        std::clamp(maxPassSeconds * double(samples) / (seconds * double(pixels)), 1.0, 1e18));
}

RenderResult render(const Scene& scene, const RenderOptions& options, Film film) {
    const Camera& cam = scene.camera;
    const RenderSettings& s = scene.settings;
    const uint32_t spp = uint32_t(s.spp);
    if (film.pixels() == 0) film = Film(cam.width, cam.height);
    if (film.width != cam.width || film.height != cam.height)
        throw Error("the film to continue is " + std::to_string(film.width) + "x" +
                    std::to_string(film.height) + ", the camera " + std::to_string(cam.width) +
                    "x" + std::to_string(cam.height));
    if (film.maxCount() > spp)
        throw Error("the film to continue has " + std::to_string(film.maxCount()) +
                    " samples per pixel, more than the " + std::to_string(spp) + " asked for");
    ThreadArena arena(options.threads);
    const int threads = arena.threads();
    // Built inside the arena: the radiance cache's first pass runs parallel loops. A cancel
    // stops its fill (a fill of 2^20 paths per record can take minutes); the time limit does
    // not: it counts the passes, and a resumed render, which fills the cache again, would stop
    // in the fill every time. A cancelled fill leaves the cache part-filled, and shouldStop()
    // below is then true from the first sample on, so no sample uses it.
    const auto cancelled = [&] {
        return options.cancel && options.cancel->load(std::memory_order_relaxed);
    };
    std::unique_ptr<const VolumePathIntegrator> built;
    arena.execute([&] { built = std::make_unique<const VolumePathIntegrator>(scene, cancelled); });
    const VolumePathIntegrator& integrator = *built;
    RenderResult result;
    const uint32_t resumedFrom = film.minCount();

    constexpr int Tile = 16;
    const int tilesX = (cam.width + Tile - 1) / Tile, tilesY = (cam.height + Tile - 1) / Tile;
    const int tiles = tilesX * tilesY;
    tbb::enumerable_thread_specific<PathCounters> counters;
    const int parts = std::max(1, options.parts);
    if (options.part < 0 || options.part >= parts)
        throw Error("render part " + std::to_string(options.part) + " of " + std::to_string(parts) +
                    " does not exist");
    uint32_t passEnd = film.minCount();
    if (options.variance && film.sumSq.empty()) {
        if (film.minCount() > 0)
            throw Error("the film to continue has no variance (it was rendered without it)");
        film.sumSq.assign(film.sum.size(), 0.0);
    }
    Progress progress("render", (long long)(spp - std::min(spp, passEnd)) * tiles,
                      options.progress);
    const auto start = std::chrono::steady_clock::now();
    const Deadline deadline(start, options.timeLimitSeconds);  // polled before every sample
    std::atomic<bool> stopped{false};
    std::atomic<int> stopReason{int(RenderStop::Completed)};
    auto shouldStop = [&] {
        if (stopped.load(std::memory_order_relaxed)) return true;
        RenderStop why = RenderStop::Completed;
        if (cancelled())
            why = RenderStop::Cancelled;
        else if (deadline.passed())
            why = RenderStop::TimeLimit;
        if (why == RenderStop::Completed) return false;
        int expected = int(RenderStop::Completed);
        stopReason.compare_exchange_strong(expected, int(why));
        stopped = true;
        return true;
    };

    // The statistics so far (between passes, when no thread is working).
    auto snapshot = [&] {
        RenderStats st;
        st.wallSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        st.threads = threads;
        st.spp = s.spp;
        st.seed = s.seed;
        st.minSamples = film.minCount();
        st.maxSamples = film.maxCount();
        st.resumedFromSamples = resumedFrom;
        st.passEnd = passEnd;
        for (const PathCounters& c : counters) st.counters.add(c);
        st.imageMeanRelativeError = film.meanRelativeError();
        st.imageMeanRelativeErrorDof = film.meanRelativeErrorDof();
        describeIntegrator(integrator, st);
        return st;
    };

    // One camera path through pixel (x, y): the jitter is the stream's first request.
    const Camera::Frame frame = cam.frame();
    auto pathSample = [&](auto&& sampler, int x, int y, PathCounters& c) {
        const Vec2 u = sampler.next2D();
        return integrator.Li(frame.generateRay(x + u.x(), y + u.y()), sampler, c);
    };

    // Passes double, unless one would outlast options.maxPassSeconds at the last pass's pace. A
    // continued film's first pass takes one sample, to learn the pace: doubling, it took as many
    // samples as every session before it, with no checkpoint in all that time (helper 71).
    uint64_t cap =
        options.maxPassSeconds >= 0 && passEnd > 0 ? 1 : std::numeric_limits<uint64_t>::max();
    const std::function<double()> passClock = options.passClock ? options.passClock : [] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
            .count();
    };
    const auto pathsSoFar = [&] {
        uint64_t n = 0;
        for (const PathCounters& c : counters) n += c.paths;
        return n;
    };
    uint64_t partPixels = 0;  // the pixels this part renders
    for (int y = options.part; y < cam.height; y += parts) partPixels += uint64_t(cam.width);
    while (passEnd < spp) {
        const uint64_t pathsBefore = pathsSoFar();
        const uint32_t end = nextPassEnd(passEnd, spp, options.stops, cap);
        const double passStart = passClock();
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const auto& r) {
                PathCounters& c = counters.local();
                for (int tile = r.begin(); tile < r.end(); ++tile) {
                    const int x0 = (tile % tilesX) * Tile, y0 = (tile / tilesX) * Tile;
                    for (int y = y0; y < std::min(y0 + Tile, cam.height); ++y) {
                        if (y % parts != options.part) continue;
                        for (int x = x0; x < std::min(x0 + Tile, cam.width); ++x) {
                            const uint64_t pixel = uint64_t(y) * cam.width + x;
                            uint32_t& n = film.count[pixel];
                            double* sum = &film.sum[3 * pixel];
                            double* sq = film.sumSq.empty() ? nullptr : &film.sumSq[3 * pixel];
                            double* ySq =
                                film.luminanceSumSq.empty() ? nullptr : &film.luminanceSumSq[pixel];
                            const SobolPixel sobolPixel(s.seed, pixel);
                            for (; n < end; ++n) {
                                if (shouldStop()) return;
                                const Spectrum L =
                                    s.sampler == SampleStream::Sobol
                                        ? pathSample(SobolSampler(sobolPixel, n), x, y, c)
                                        : pathSample(Rng::forSample(s.seed, pixel, n), x, y, c);
                                if (L.allFinite()) {
                                    sum[0] += L[0], sum[1] += L[1], sum[2] += L[2];
                                    if (ySq) *ySq += sqr(luminance(L));
                                    if (sq)
                                        sq[0] += L[0] * L[0], sq[1] += L[1] * L[1],
                                            sq[2] += L[2] * L[2];
                                } else
                                    ++c.nonFiniteSamples;
                            }
                        }
                    }
                    progress.advance(end - passEnd);
                }
            });
        });
        if (stopped) break;
        const double seconds = passClock() - passStart;
        if (options.maxPassSeconds >= 0 && seconds > 0)
            cap = passSampleCap(options.maxPassSeconds, seconds, pathsSoFar() - pathsBefore,
                                partPixels);
        passEnd = end;
        if (options.afterPass) options.afterPass(film, snapshot());
    }
    progress.done();
    result.image = film.image();

    result.stats = snapshot();
    result.stats.stop = RenderStop(stopReason.load());
    result.film = std::move(film);
    return result;
}

}  // namespace shvol
