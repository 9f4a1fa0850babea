// The light-sampling strategies in isolation: at a point with nothing in the way, estimate the
// in-scattered radiance I(ω₀) = ∫ p(ω₀·ω) L(ω) dω under a sky with one sample per strategy (one
// light and one phase sample for the MIS combinations), and report the relative variance
// Var[X]/I² averaged over propagation directions ω₀, the time per estimate, and the efficiency
// 1/(relative variance × time) — what a strategy can buy at most in a render, before
// transmittance, free flights and path throughput add their own noise.
//
// Directions ω₀ are drawn uniformly over the sphere ("all"), or within 25° of the sun
// ("towards sun": light travelling towards the sun scatters it forward into the eye, as in a
// backlit cloud), the sun being the brightest sky cell.
//
// Usage: validate_product SKY.exr|studio [OUT.csv [STUDIO_SKY.exr]]
// (writes a CSV and prints a Markdown table; with a third argument the studio sky is also written
// as an EXR, for renders)
// "studio" is a synthetic 1024×512 sky of eight equal lights, discs of 4° radius and radiance 200,
// spread over the sphere, on a background of 0.05: several bright sources of similar power
// instead of one sun.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "shvol/core/rng.h"
#include "shvol/io/exr.h"
#include "shvol/lights/environment.h"
#include "shvol/lights/product_sampler.h"
#include "shvol/phase/henyey_greenstein_phase.h"
#include "shvol/phase/zonal_fit.h"

using namespace shvol;

namespace {

Image studioSky() {
    Image img(1024, 512);
    const Vec3 lights[8] = {sphericalDirection(0.9, 0.3),  sphericalDirection(0.5, 1.9),
                            sphericalDirection(0.2, 3.4),  sphericalDirection(-0.1, 5.0),
                            sphericalDirection(-0.4, 0.9), sphericalDirection(-0.7, 2.7),
                            sphericalDirection(0.6, 4.4),  sphericalDirection(-0.2, 6.0)};
    const double cosR = std::cos(4 * Pi / 180);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const Vec3 w = latLongDirection(LatLongMapping::Blender, (x + 0.5) / img.width,
                                            (y + 0.5) / img.height);
            double L = 0.05;
            for (const Vec3& l : lights)
                if (w.dot(l) >= cosR) L = 200;
            img.set(x, y, Spectrum::Constant(L));
        }
    return img;
}

struct Draw {
    Vec3 w;
    double pdf;
};

struct Result {
    double relVariance, nsPerEstimate;
};

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: validate_product SKY.exr [OUT.csv]\n");
        return 2;
    }
    const std::string skyName = argv[1];
    const Image skyImage = skyName == "studio" ? studioSky() : readExr(skyName);
    if (skyName == "studio" && argc > 3) writeExr(argv[3], skyImage);
    const Environment env = Environment::image(skyImage, 1.0, 0.0, false);
    const SkyHierarchy sky = env.skyHierarchy();
    const int kDirections = 64, kSamples = 20000;
    // The sun: the brightest leaf of the sky hierarchy.
    Vec3 sun(0, 0, 1);
    double brightest = -1;
    const int res = sky.resolution();
    for (int iz = 0; iz < res; ++iz)
        for (int ip = 0; ip < res; ++ip)
            if (const double a = sky.average(sky.levels(), iz, ip); a > brightest)
                brightest = a,
                sun = sphericalDirection(-1 + (iz + 0.5) * 2.0 / res, (ip + 0.5) * TwoPi / res);
    std::ofstream csv(argc > 2 ? argv[2] : "validate_product.csv");
    csv << "directions,g,order,strategy,relative_variance,ns_per_estimate,efficiency\n";
    std::printf(
        "| directions | g | order | strategy | relative variance | ns/estimate | "
        "efficiency |\n");
    std::printf("|---|---:|---:|---|---:|---:|---:|\n");
    const Frame sunFrame(sun);
    for (const char* directions : {"all", "towards sun"})
        for (double g : {0.0, 0.5, 0.8, 0.95}) {
            const HenyeyGreensteinPhase hg(g);
            for (int order : {4, 8, 16}) {
                if (g == 0.0 && order != 8) continue;
                const ProductSampler ps(sky, order);
                const ZonalFit fit = fitZonal([&](double mu) { return henyeyGreenstein(mu, g); },
                                              order, SHWindow::Hann);
                const double beta = ps.defensiveShare(fit.minValue);
                const int bands = ProductSampler::significantBands(fit.p);
                ProductSampler::ZonalLobe lobe;
                // Strategies: a light draw (direction, pdf) and whether phase sampling joins by
                // MIS.
                using LightFn = std::function<Draw(const Vec2&)>;
                using PdfFn = std::function<double(const Vec3&)>;
                struct Strategy {
                    const char* name;
                    LightFn light;
                    PdfFn lightPdf;
                    bool mis;
                };
                const LightFn envLight = [&](const Vec2& u) {
                    const LightSample s = env.sample(u);
                    return Draw{s.wi, s.pdf};
                };
                const LightFn skyLight = [&](const Vec2& u) {
                    const WarpSample s = sky.warp(u);
                    return Draw{s.direction(), s.pdf};
                };
                const LightFn productLight = [&](const Vec2& u) {
                    const WarpSample s = ps.warp(lobe, beta, u);
                    return Draw{s.direction(), s.pdf};
                };
                const PdfFn envPdf = [&](const Vec3& w) { return env.pdf(w); };
                const PdfFn skyPdf = [&](const Vec3& w) { return sky.pdf(w); };
                const PdfFn productPdf = [&](const Vec3& w) { return ps.pdf(lobe, beta, w); };
                const Strategy strategies[] = {
                    {"environment", envLight, envPdf, false},
                    {"wavelet", skyLight, skyPdf, false},
                    {"product", productLight, productPdf, false},
                    {"mis_environment", envLight, envPdf, true},
                    {"mis_product", productLight, productPdf, true},
                };
                for (const Strategy& st : strategies) {
                    Rng rng(7, 11);
                    const bool usesLobe = std::string(st.name).find("product") != std::string::npos;
                    double relVar = 0, seconds = 0;
                    for (int d = 0; d < kDirections; ++d) {
                        const Vec3 wo =
                            directions[0] == 'a'
                                ? sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform())
                                : sunFrame.toWorld(sphericalDirection(
                                      1 - rng.uniform() * (1 - std::cos(25 * Pi / 180)),
                                      TwoPi * rng.uniform()));
                        double s1 = 0, s2 = 0;
                        const auto t0 = std::chrono::steady_clock::now();
                        for (int i = 0; i < kSamples; ++i) {
                            // The per-event work: (rotate the lobe,) draw, evaluate, weight.
                            if (usesLobe) ps.rotateZonal(fit.p.data(), wo, lobe, bands);
                            double x = 0;
                            const Draw l = st.light(rng.uniform2());
                            if (l.pdf > 0) {
                                const double f = hg.eval(wo, l.w);
                                const double wl = st.mis ? l.pdf / (l.pdf + hg.pdf(wo, l.w)) : 1.0;
                                x += wl * f * luminance(env.Le(l.w)) / l.pdf;
                            }
                            if (st.mis) {
                                const PhaseSample p = hg.sample(wo, rng.uniform2());
                                const double pl = st.lightPdf(p.wi);
                                x += p.pdf / (p.pdf + pl) * p.value * luminance(env.Le(p.wi)) /
                                     p.pdf;
                            }
                            s1 += x, s2 += x * x;
                        }
                        seconds +=
                            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
                                .count();
                        const double mean = s1 / kSamples;
                        relVar += (s2 / kSamples - mean * mean) / (mean * mean);
                    }
                    relVar /= kDirections;
                    const double ns = 1e9 * seconds / (double(kDirections) * kSamples);
                    const double eff = 1 / (relVar * ns * 1e-9);
                    std::printf("| %s | %.2f | %d | %s | %.4g | %.0f | %.3g |\n", directions, g,
                                order, st.name, relVar, ns, eff);
                    csv << directions << "," << g << "," << order << "," << st.name << "," << relVar
                        << "," << ns << "," << eff << "\n";
                }
            }
        }
    return 0;
}
