// Sample streams: a path's 2D request from SobolSampler (shuffled, Owen-scrambled (0,2)-sequence)
// against independent PCG32 numbers, per sample and per request, with same-run ratios.
#include <benchmark/benchmark.h>

#include "ratio_reporter.h"
#include "shvol/sampling/sobol_sampler.h"

namespace shvol {
namespace {

constexpr int kRequests = 8;  // a path of a few bounces: jitter, then flight and phase pairs

void IndependentPath(benchmark::State& state) {
    uint32_t n = 0;
    for (auto _ : state) {
        Rng rng = Rng::forSample(1, 42, n++);
        for (int d = 0; d < kRequests; ++d) benchmark::DoNotOptimize(rng.next2D());
    }
    state.SetItemsProcessed(state.iterations() * kRequests);
}
BENCHMARK(IndependentPath);

void SobolPath(benchmark::State& state) {
    uint32_t n = 0;
    const SobolPixel pixel(1, 42);
    for (auto _ : state) {
        SobolSampler s(pixel, n++);
        for (int d = 0; d < kRequests; ++d) benchmark::DoNotOptimize(s.next2D());
    }
    state.SetItemsProcessed(state.iterations() * kRequests);
}
BENCHMARK(SobolPath);

void SobolSecondDimensionTable(benchmark::State& state) {
    uint32_t n = 0x9e3779b9u;
    for (auto _ : state) benchmark::DoNotOptimize(sobolSecondDimension(n += 0x9e3779b9u));
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(SobolSecondDimensionTable);

void SobolSecondDimensionBitwise(benchmark::State& state) {
    uint32_t n = 0x9e3779b9u;
    for (auto _ : state) benchmark::DoNotOptimize(sobolSecondDimensionBitwise(n += 0x9e3779b9u));
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(SobolSecondDimensionBitwise);

}  // namespace
}  // namespace shvol

int main(int argc, char** argv) {
    return shvol::bench::runWithRatios(
        argc, argv,
        {{"SobolPath", "IndependentPath"},
         {"SobolSecondDimensionTable", "SobolSecondDimensionBitwise"}});
}
