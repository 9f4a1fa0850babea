// Light-sampling throughput: the environment's lat-long sampler, the sky hierarchy (wavelet) and
// the product sampler (rotated zonal lobe × sky) at orders 4–32 on 512² and 2048² skies, one
// core, and the environment's texel draw against inverting each row's CDF. Prints Google
// Benchmark's table, then same-run ratios to an environment sample.
#include <benchmark/benchmark.h>

#include <memory>

#include "ratio_reporter.h"
#include "shvol/core/rng.h"
#include "shvol/lights/environment.h"
#include "shvol/lights/product_sampler.h"
#include "shvol/sampling/distribution_2d.h"
#include "shvol/sampling/texel_sampler.h"

using namespace shvol;

namespace {

/// A 2048×1024 sky: a gradient, a ground and a 0.53° sun 1e5 times brighter.
const Image& skyImage() {
    static const Image img = [] {
        Image im(2048, 1024);
        const Vec3 sun = sphericalDirection(0.5, 1.0);
        const double cosSun = std::cos(0.53 * Pi / 360);
        for (int y = 0; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x) {
                const Vec3 w = latLongDirection(LatLongMapping::Blender, (x + 0.5) / im.width,
                                                (y + 0.5) / im.height);
                Spectrum L = w.z() > 0 ? Spectrum(0.3 + 0.5 * (1 - w.z()), 0.5, 1.0)
                                       : Spectrum(0.1, 0.1, 0.1);
                if (w.dot(sun) > cosSun) L *= 1e5;
                im.set(x, y, L);
            }
        return im;
    }();
    return img;
}

const SkyHierarchy& sky(int levels, size_t K = 0) {
    static std::map<std::pair<int, size_t>, std::unique_ptr<SkyHierarchy>> cache;
    auto& h = cache[{levels, K}];
    if (!h) {
        SkyHierarchy::LatLongSource src;
        src.image = &skyImage();
        h = std::make_unique<SkyHierarchy>(SkyHierarchy::fromLatLong(src, levels, K));
    }
    return *h;
}

const Vec3 kAxis = Vec3(0.3, -0.5, 0.8).normalized();

/// Hann-windowed zonal coefficients of HG g = 0.8 at order n.
std::vector<double> hg(int n) {
    std::vector<double> p(n);
    for (int l = 0; l < n; ++l)
        p[l] =
            std::pow(0.8, l) * std::sqrt((2 * l + 1) / FourPi) * 0.5 * (1 + std::cos(Pi * l / n));
    return p;
}

/// That lobe rotated to kAxis, in the fast zonal form the renderer uses.
ProductSampler::ZonalLobe lobe(const ProductSampler& ps) {
    ProductSampler::ZonalLobe z;
    ps.rotateZonal(hg(ps.order()).data(), kAxis, z);
    return z;
}

void EnvironmentSample(benchmark::State& state) {
    const Environment env = Environment::image(skyImage(), 1, 0, false);
    Rng rng(1, 1);
    double sink = 0;
    for (auto _ : state) sink += env.sample(rng.uniform2()).pdf;
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(EnvironmentSample);

/// The 2048×1024 sky's weights as Environment::image sets them: luminance · sin θ.
const std::vector<double>& skyWeights() {
    static const std::vector<double> w = [] {
        const Image& im = skyImage();
        std::vector<double> v(size_t(im.width) * im.height);
        for (int y = 0; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x)
                v[size_t(y) * im.width + x] =
                    luminance(im.at(x, y)) * std::sin(Pi * (y + 0.5) / im.height);
        return v;
    }();
    return w;
}

/// A texel and its RGB for each u, each draw waiting for the last (as a path's do: u is moved by
/// 0·pdf): the texel sampler (row by inversion, texel by alias, one record)...
void TexelDraw(benchmark::State& state) {
    const Image& im = skyImage();
    const TexelSampler s(skyWeights().data(), im.rgb.data(), im.width, im.height);
    Rng rng(1, 1);
    double last = 0, sink = 0;
    for (auto _ : state) {
        const TexelSampler::Draw d = s.sample(rng.uniform2() + Vec2::Constant(0 * last));
        last = d.pdf;
        sink += d.rgb[0];
    }
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(TexelDraw);

/// ... and inverting the row's CDF too (Distribution2D), then reading the image.
void RowInversionDraw(benchmark::State& state) {
    const Image& im = skyImage();
    const Distribution2D d2(skyWeights().data(), im.width, im.height);
    Rng rng(1, 1);
    double last = 0, sink = 0;
    for (auto _ : state) {
        double pdf;
        Eigen::Vector2i texel;
        d2.sampleContinuous(rng.uniform2() + Vec2::Constant(0 * last), &pdf, &texel);
        last = pdf;
        sink += im.at(texel.x(), texel.y())[0];
    }
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(RowInversionDraw);

void WaveletSample(benchmark::State& state) {
    const SkyHierarchy& h = sky(int(state.range(0)), size_t(state.range(1)));
    Rng rng(1, 1);
    double sink = 0;
    for (auto _ : state) sink += h.warp(rng.uniform2()).pdf;
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(WaveletSample)->Args({9, 0})->Args({11, 0})->Args({11, 10000});

/// Warps sets of 64 random points with warp(u, out); items are points.
template <class Warp>
void pointSets(benchmark::State& state, const Warp& warp) {
    Rng rng(1, 1);
    std::vector<Vec2> u(64);
    std::vector<WarpSample> out;
    double sink = 0;
    for (auto _ : state) {
        for (Vec2& p : u) p = rng.uniform2();
        warp(u, out);
        sink += out[0].pdf;
    }
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations() * 64);
}

void WaveletPointSet(benchmark::State& state) {
    const SkyHierarchy& h = sky(int(state.range(0)));
    pointSets(state, [&](const auto& u, auto& out) { h.warp(u, out); });
}
BENCHMARK(WaveletPointSet)->Arg(11);

void ProductSample(benchmark::State& state) {
    const ProductSampler ps(sky(int(state.range(1))), int(state.range(0)));
    const ProductSampler::ZonalLobe c = lobe(ps);
    Rng rng(1, 1);
    double sink = 0;
    for (auto _ : state) sink += ps.warp(c, rng.uniform2()).pdf;
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(ProductSample)->ArgsProduct({{4, 8, 16, 32}, {9, 11}});

/// Per scattering event: rotate the lobe to a new axis, then draw one sample.
void ProductEvent(benchmark::State& state) {
    const ProductSampler ps(sky(int(state.range(1))), int(state.range(0)));
    const std::vector<double> p = hg(ps.order());
    ProductSampler::ZonalLobe c;
    Rng rng(1, 1);
    double sink = 0;
    for (auto _ : state) {
        ps.rotateZonal(p.data(), sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform()),
                       c);
        sink += ps.warp(c, rng.uniform2()).pdf;
    }
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(ProductEvent)->ArgsProduct({{4, 8, 16, 32}, {11}});

void ProductPointSet(benchmark::State& state) {
    const ProductSampler ps(sky(int(state.range(1))), int(state.range(0)));
    const ProductSampler::ZonalLobe c = lobe(ps);
    pointSets(state, [&](const auto& u, auto& out) { ps.warp(c, u, out); });
}
BENCHMARK(ProductPointSet)->ArgsProduct({{4, 8, 16, 32}, {9, 11}});

void ProductPdf(benchmark::State& state) {
    const ProductSampler ps(sky(int(state.range(1))), int(state.range(0)));
    const ProductSampler::ZonalLobe c = lobe(ps);
    Rng rng(1, 1);
    double sink = 0;
    for (auto _ : state)
        sink += ps.pdf(c, sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform()));
    benchmark::DoNotOptimize(sink);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(ProductPdf)->ArgsProduct({{4, 8, 16, 32}, {9, 11}});

void SkyBuild(benchmark::State& state) {
    SkyHierarchy::LatLongSource src;
    src.image = &skyImage();
    for (auto _ : state) {
        const SkyHierarchy h = SkyHierarchy::fromLatLong(src, int(state.range(0)));
        benchmark::DoNotOptimize(h.rootAverage());
    }
}
BENCHMARK(SkyBuild)->Arg(9)->Arg(11)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::pair<std::string, std::string>> pairs;
    for (const char* levels : {"9", "11"}) {
        for (const char* n : {"4", "8", "16", "32"}) {
            const std::string args = std::string(n) + "/" + levels;
            for (const char* b : {"ProductSample/", "ProductPointSet/", "ProductPdf/"})
                pairs.push_back({b + args, "EnvironmentSample"});
        }
        pairs.push_back({std::string("WaveletSample/") + levels + "/0", "EnvironmentSample"});
    }
    for (const char* n : {"4", "8", "16", "32"})
        pairs.push_back({std::string("ProductEvent/") + n + "/11", "EnvironmentSample"});
    pairs.push_back({"WaveletSample/11/10000", "WaveletSample/11/0"});
    pairs.push_back({"TexelDraw", "RowInversionDraw"});
    return bench::runWithRatios(
        argc, argv, pairs,
        "Same-run ratios (items/s; below 1: slower than an environment sample):");
}
