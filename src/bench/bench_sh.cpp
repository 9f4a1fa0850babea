// Google Benchmark for the SH maths layer: basis evaluation, rotation matrices, rectangle
// integrals. Run: build/bench_sh (one core).
#include <benchmark/benchmark.h>

#include <vector>

#include "ratio_reporter.h"
#include "shvol/core/math.h"
#include "shvol/sh/hsh.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_integrals.h"
#include "shvol/sh/sh_rotation.h"

using namespace shvol;
using namespace shvol::sh;

namespace {

std::vector<Vec3> directions(int k) {
    std::vector<Vec3> d;
    for (int i = 0; i < k; ++i) {
        const double z = -1.0 + (2.0 * i + 1.0) / k;
        d.push_back(sphericalDirection(z, 2.399963229728653 * i));  // golden-angle spiral
    }
    return d;
}

void BM_ShEval(benchmark::State& st) {
    const int n = static_cast<int>(st.range(0));
    const auto dirs = directions(256);
    std::vector<double> out(n * n);
    size_t i = 0;
    for (auto _ : st) {
        shEval(n, dirs[i++ & 255], out.data());
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
}
BENCHMARK(BM_ShEval)->Arg(3)->Arg(4)->Arg(5)->Arg(10)->Arg(20);

void BM_ShEvalRecurrence(benchmark::State& st) {
    const int n = static_cast<int>(st.range(0));
    const auto dirs = directions(256);
    std::vector<double> out(n * n);
    size_t i = 0;
    for (auto _ : st) {
        shEvalRecurrence(n, dirs[i++ & 255], out.data());
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
}
BENCHMARK(BM_ShEvalRecurrence)->Arg(3)->Arg(4)->Arg(5);

void BM_HshEval(benchmark::State& st) {
    const int n = static_cast<int>(st.range(0));
    auto dirs = directions(512);
    for (auto& d : dirs) d.z() = std::fabs(d.z());
    std::vector<double> out(n * n);
    size_t i = 0;
    for (auto _ : st) {
        hshEval(n, dirs[i++ & 511], out.data());
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
}
BENCHMARK(BM_HshEval)->Arg(5)->Arg(10);

void BM_RotationBuild(benchmark::State& st) {
    const int n = static_cast<int>(st.range(0));
    const auto method = static_cast<RotationMethod>(st.range(1));
    double a = 0.1;
    { ShRotation warm(n, rotationZYZ(0.3, 1.0, 0.2), method); }  // fills the L_y cache
    for (auto _ : st) {
        a += 1e-3;
        ShRotation R(n, rotationZYZ(a, 1.1, -0.4), method);
        benchmark::DoNotOptimize(R.bands.data());
    }
    st.SetLabel(method == RotationMethod::IvanicRuedenberg ? "IR"
                : method == RotationMethod::EulerEigen     ? "EulerEigen"
                                                           : "Auto");
}
BENCHMARK(BM_RotationBuild)
    ->Args({5, 0})
    ->Args({10, 0})
    ->Args({20, 0})
    ->Args({5, 1})
    ->Args({10, 1})
    ->Args({20, 1})
    ->Unit(benchmark::kMicrosecond);

void BM_RotationApply(benchmark::State& st) {
    const int n = static_cast<int>(st.range(0));
    const ShRotation R(n, rotationZYZ(0.3, 1.1, -0.4));
    std::vector<double> in(n * n, 0.5), out(n * n);
    for (auto _ : st) {
        R.apply(in.data(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
}
BENCHMARK(BM_RotationApply)->Arg(5)->Arg(10)->Arg(20);

/// Three vectors of 16 bands (an RGB radiance cache record of order 8) rotated by a new R each
/// time (items: rotations): /0 ShRotation's band matrices built and applied, /1
/// ShVectorRotation. Each R is a small tilt with a twist, as between neighbouring records.
void ShRotateVectors(benchmark::State& st) {
    const int n = 16, count = 3;
    const bool fast = st.range(0) == 1;
    const ShVectorRotation rotation(n);
    std::vector<double> in(size_t(n * n * count), 0.5), out(in.size());
    double a = 0;
    for (auto _ : st) {
        a += 0.01;
        const Eigen::Matrix3d R = rotationZYZ(a, 0.2, 1.0 - a);
        if (fast) {
            rotation.apply(R, in.data(), out.data(), count);
        } else {
            const ShRotation slow(n, R);
            for (int j = 0; j < count; ++j) slow.apply(&in[j * n * n], &out[j * n * n]);
        }
        benchmark::DoNotOptimize(out.data());
    }
    st.SetItemsProcessed(int64_t(st.iterations()));
}
BENCHMARK(ShRotateVectors)->Arg(0)->Arg(1);

void BM_RotateZonal(benchmark::State& st) {
    const int n = static_cast<int>(st.range(0));
    const auto dirs = directions(256);
    std::vector<double> p(n, 0.1), out(n * n);
    size_t i = 0;
    for (auto _ : st) {
        rotateZonal(n, p.data(), dirs[i++ & 255], out.data());
        benchmark::DoNotOptimize(out.data());
    }
}
BENCHMARK(BM_RotateZonal)->Arg(5)->Arg(20);

// Rectangle integrals: "wide" cells (recurrence) and "narrow" cells (< threshold: θ-panel rule).
void BM_RectIntegrals(benchmark::State& st) {
    const int n = static_cast<int>(st.range(0));
    const bool narrow = st.range(1) != 0;
    std::vector<double> out(n * n), work(rectIntegralsWorkSize(n));
    double z0 = -0.8;
    const double w = narrow ? 1e-6 : 0.25;
    for (auto _ : st) {
        z0 += 1e-7;
        if (z0 > 0.5) z0 = -0.8;
        shRectIntegrals(n, z0, z0 + w, 0.3, 0.3 + (narrow ? 1e-6 : 0.8), out.data(), work.data());
        benchmark::DoNotOptimize(out.data());
    }
    st.SetLabel(narrow ? "narrow dz=1e-6" : "wide dz=0.25");
}
BENCHMARK(BM_RectIntegrals)->Args({5, 0})->Args({5, 1})->Args({20, 0})->Args({20, 1});

void BM_LegendreIntegralsZonal(benchmark::State& st) {
    const int n = static_cast<int>(st.range(0));
    std::vector<double> out(n);
    double z0 = -0.8;
    for (auto _ : st) {
        z0 += 1e-7;
        if (z0 > 0.5) z0 = -0.8;
        legendreIntegralsZonal(n, z0, z0 + 0.25, out.data());
        benchmark::DoNotOptimize(out.data());
    }
}
BENCHMARK(BM_LegendreIntegralsZonal)->Arg(5)->Arg(20)->Arg(100);

}  // namespace

int main(int argc, char** argv) {
    return shvol::bench::runWithRatios(argc, argv, {{"ShRotateVectors/1", "ShRotateVectors/0"}},
                                       "Same-run ratios (items/s; ShRotateVectors: /1 "
                                       "ShVectorRotation, /0 ShRotation built and applied):");
}
