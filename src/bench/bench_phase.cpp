// Sampling throughput of the SH samplers against analytic Henyey–Greenstein sampling, one core.
// Prints Google Benchmark's table, then the same-run ratios asked for in the SH sampling issue.
// Also: HG sampling with the density evaluated and sincos (as before the closed-form density and
// cosSin2Pi), and cosSin2Pi against sincos of 2πu.
#include <benchmark/benchmark.h>

#include <cstdio>

#include "ratio_reporter.h"
#include "shvol/core/rng.h"
#include "shvol/phase/henyey_greenstein_phase.h"
#include "shvol/phase/zonal_fit.h"
#include "shvol/sampling/sh_sampler.h"
#include "shvol/sampling/zonal_sh_sampler.h"
#include "shvol/sh/sh_basis.h"

using namespace shvol;

namespace {

const Vec3 kAxis = Vec3(0.3, -0.5, 0.8).normalized();

/// A Henyey–Greenstein lobe (g = 0.8) of order n rotated to kAxis, plus a small constant.
std::vector<double> lobe(int n) {
    std::vector<double> y(n * n), f(n * n);
    sh::shEval(n, kAxis, y.data());
    for (int l = 0; l < n; ++l)
        for (int m = -l; m <= l; ++m) f[l * (l + 1) + m] = std::pow(0.8, l) * y[l * (l + 1) + m];
    f[0] += 0.05 * std::sqrt(FourPi);
    return f;
}

void HGAnalytic(benchmark::State& state) {
    const HenyeyGreensteinPhase hg(0.8);
    Rng rng(1, 1);
    double sink = 0;
    for (auto _ : state) {
        const PhaseSample x = hg.sample(kAxis, rng.uniform2());
        sink += x.wi.z() + x.pdf;
    }
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(HGAnalytic);

/// HenyeyGreensteinPhase::sample with the density from henyeyGreenstein at the sampled cosine
/// and the azimuth from sincos, as before 2026-12-01 (the sampler's cosine is today's). Both
/// benchmarks build the frame per sample and keep the direction and the density.
void HGEvalAndSincos(benchmark::State& state) {
    const double g = 0.8;
    const HenyeyGreensteinSampler sampler(g);
    Rng rng(1, 1);
    double sink = 0;
    for (auto _ : state) {
        const Vec2 u = rng.uniform2();
        const double mu = sampler(u.x()).angle.mu;
        sink += Frame(kAxis).toWorld(sphericalDirection(mu, TwoPi * u.y())).z() +
                henyeyGreenstein(mu, g);
    }
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(HGEvalAndSincos);

/// The azimuth's cos and sin, as the analytic samplers compute them (cosSin2Pi) and as they were.
Vec2 sincosOf2PiU(double u) {
    return cosSin(TwoPi * u);
}
template <Vec2 (*CosSin)(double)>
void Azimuth(benchmark::State& state) {
    Rng rng(1, 1);
    double sink = 0;
    for (auto _ : state) sink += CosSin(rng.uniform()).x();
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK_TEMPLATE(Azimuth, cosSin2Pi);
BENCHMARK_TEMPLATE(Azimuth, sincosOf2PiU);

void ZonalSH(benchmark::State& state) {
    const int n = int(state.range(0));
    const ZonalFit fit = fitZonal([](double mu) { return henyeyGreenstein(mu, 0.8); }, n);
    const ZonalSHSampler s(fit.p);
    Rng rng(1, 1);
    double sink = 0, pdf;
    for (auto _ : state) sink += s.warp(kAxis, rng.uniform2(), &pdf).z() + pdf;
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(ZonalSH)->Arg(16)->Arg(64);

void SHSingle(benchmark::State& state) {
    const int n = int(state.range(0));
    const auto f = lobe(n);
    const SHSampler s(n, f.data(), SHSampler::Mode::Tables);
    Rng rng(1, 1);
    double sink = 0;
    for (auto _ : state) {
        const WarpSample w = s.warp(rng.uniform2());
        sink += w.z + w.pdf;
    }
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(SHSingle)->Arg(3)->Arg(5)->Arg(9)->Arg(13)->Arg(20);

void SHPointSet(benchmark::State& state) {
    const int n = int(state.range(0)), count = 4096;
    const auto f = lobe(n);
    const SHSampler s(n, f.data(), SHSampler::Mode::Tables);
    Rng rng(1, 1);
    std::vector<Vec2> u(count);
    std::vector<WarpSample> out;
    for (auto _ : state) {
        state.PauseTiming();
        for (auto& p : u) p = rng.uniform2();
        state.ResumeTiming();
        s.warp(u, out);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * count);
}
BENCHMARK(SHPointSet)->Arg(3)->Arg(5)->Arg(9)->Arg(13)->Arg(20);

void SHOnTheFly(benchmark::State& state) {
    const int n = int(state.range(0));
    const auto f = lobe(n);
    const SHSampler s(n, f.data(), SHSampler::Mode::OnTheFly, 8);
    Rng rng(1, 1);
    double sink = 0;
    for (auto _ : state) sink += s.warp(rng.uniform2()).z;
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(SHOnTheFly)->Arg(5)->Arg(20);

void SHOnTheFlyPointSet(benchmark::State& state) {
    const int n = int(state.range(0)), count = 4096;
    const auto f = lobe(n);
    const SHSampler s(n, f.data(), SHSampler::Mode::OnTheFly, 8);
    Rng rng(1, 1);
    std::vector<Vec2> u(count);
    std::vector<WarpSample> out;
    for (auto& p : u) p = rng.uniform2();
    for (auto _ : state) {
        s.warp(u, out);
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * count);
}
BENCHMARK(SHOnTheFlyPointSet)->Arg(5)->Arg(20);

void SHBuildTables(benchmark::State& state) {
    const int n = int(state.range(0));
    const auto f = lobe(n);
    for (auto _ : state) {
        SHSampler s(n, f.data(), SHSampler::Mode::Tables);
        benchmark::DoNotOptimize(&s);
    }
}
BENCHMARK(SHBuildTables)->Arg(5)->Arg(20)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
    return bench::runWithRatios(argc, argv,
                                {{"ZonalSH/16", "HGAnalytic"},
                                 {"ZonalSH/64", "HGAnalytic"},
                                 {"SHSingle/20", "SHSingle/5"},
                                 {"SHPointSet/20", "SHPointSet/5"},
                                 {"SHPointSet/5", "SHSingle/5"},
                                 {"SHSingle/5", "HGAnalytic"},
                                 {"SHOnTheFly/20", "SHOnTheFly/5"},
                                 {"HGAnalytic", "HGEvalAndSincos"},
                                 {"Azimuth<cosSin2Pi>", "Azimuth<sincosOf2PiU>"}});
}
