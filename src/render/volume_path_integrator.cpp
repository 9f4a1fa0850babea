#include "shvol/render/volume_path_integrator.h"

#include <chrono>

#include "shvol/phase/zonal_fit.h"

namespace shvol {

void PathCounters::add(const PathCounters& o) {
    paths += o.paths;
    scatteringEvents += o.scatteringEvents;
    phaseSamples += o.phaseSamples;
    lightSamples += o.lightSamples;
    productSamples += o.productSamples;
    productPdfs += o.productPdfs;
    transmittanceRays += o.transmittanceRays;
    nonFiniteSamples += o.nonFiniteSamples;
    tracking.densityLookups += o.tracking.densityLookups;
    tracking.segments += o.tracking.segments;
}

VolumePathIntegrator::VolumePathIntegrator(const Scene& scene)
    : scene_(scene), effects_(Effects::of(scene)) {
    if (!effects_.nextEvent || effects_.lightSampling == LightSampling::Environment) return;
    const auto start = std::chrono::steady_clock::now();
    const RenderSettings& s = scene.settings;
    sky_ =
        std::make_unique<const SkyHierarchy>(scene.environment.skyHierarchy(s.waveletCoefficients));
    effects_.skyCompressed = sky_->compressed();
    if (effects_.lightSampling == LightSampling::Product) {
        product_ = std::make_unique<const ProductSampler>(*sky_, s.productOrder, s.productDepth);
        const Vec3 z(0, 0, 1);
        for (const auto& m : scene.media) {
            // The lobe only shapes the pdf: a Hann-windowed fit rings least (zonal_fit.h).
            const PhaseFunction& phase = m->phase();
            const ZonalFit fit =
                fitZonal([&](double mu) { return phase.eval(z, sphericalDirection(mu, 0)); },
                         s.productOrder, SHWindow::Hann);
            // Without MIS the product sampler alone must reach every lit direction: the
            // defensive share then guards against cells whose lobe mass rounds to ≤ 0 even for
            // a fit that is non-negative at its quadrature nodes.
            const double beta = effects_.mis == MisHeuristic::None
                                    ? ProductSampler::kDefensiveFraction
                                    : product_->defensiveShare(fit.minValue);
            lobes_.push_back({fit.p, ProductSampler::significantBands(fit.p), beta});
        }
    }
    setupSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double VolumePathIntegrator::sampleCollision(const Ray& ray, Rng& rng, PathCounters& c,
                                             int* medium) const {
    double tHit = NoCollision;
    *medium = -1;
    for (size_t i = 0; i < scene_.media.size(); ++i) {
        // Only collisions before the nearest one found so far matter.
        const double t = scene_.media[i]->sampleCollision(ray, tHit, rng, c.tracking);
        if (t < tHit) tHit = t, *medium = int(i);
    }
    return tHit;
}

double VolumePathIntegrator::transmittance(const Ray& ray, Rng& rng, PathCounters& c) const {
    ++c.transmittanceRays;
    double T = 1;
    for (const auto& m : scene_.media) {
        T *= m->transmittance(ray, NoCollision, scene_.settings.transmittance, rng, c.tracking);
        if (T <= 0) return 0;
    }
    return T;
}

double VolumePathIntegrator::misWeight(double pa, double pb) const {
    if (effects_.mis == MisHeuristic::None) return 1;
    // Written in the ratio r = p_b/p_a so that neither tiny pdfs (squares underflowing to 0/0)
    // nor huge ones (g → 1) can make the weight NaN; pa = 0 gives 0, pb = 0 or ∞ gives 1 or 0.
    if (!(pa > 0)) return 0;
    const double r = pb / pa;
    return effects_.mis == MisHeuristic::Power ? 1 / (1 + r * r) : 1 / (1 + r);
}

VolumePathIntegrator::LightDraw VolumePathIntegrator::sampleLight(const EventLobe& lobe,
                                                                  const Vec2& u,
                                                                  PathCounters& c) const {
    const Environment& env = scene_.environment;
    WarpSample s;
    switch (effects_.lightSampling) {
        case LightSampling::Environment: {
            const LightSample ls = env.sample(u);
            return {ls.wi, ls.Le, ls.pdf};
        }
        case LightSampling::Wavelet:
            s = sky_->sample(u);
            break;
        case LightSampling::Product:
            ++c.productSamples;
            s = product_->sample(lobe.lobe, lobe.beta, u);
            break;
    }
    if (!(s.pdf > 0)) return {Vec3(0, 0, 1), Spectrum::Zero(), 0.0};
    const Vec3 w = s.direction();
    return {w, env.Le(w), s.pdf};
}

double VolumePathIntegrator::lightPdf(const EventLobe& lobe, const Vec3& w, PathCounters& c) const {
    switch (effects_.lightSampling) {
        case LightSampling::Wavelet:
            return sky_->pdf(w);
        case LightSampling::Product:
            ++c.productPdfs;
            return product_->pdf(lobe.lobe, lobe.beta, w);
        default:
            return scene_.environment.pdf(w);
    }
}

template <typename Sampler>
Spectrum VolumePathIntegrator::Li(Ray ray, Sampler& sampler, PathCounters& c) const {
    Rng& rng = sampler.rng();
    ++c.paths;
    const Environment& env = scene_.environment;
    if (!effects_.volumes) return env.Le(ray.d);
    if (!effects_.scattering) return transmittance(ray, rng, c) * env.Le(ray.d);

    const RenderSettings& s = scene_.settings;
    const bool product = product_ != nullptr;
    Spectrum L = Spectrum::Zero(), beta = Spectrum::Ones();
    double phasePdf = 0;  // pdf of the phase sample that started this ray; 0 for camera rays
    EventLobe lobe;       // the last scattering event's lobe (product sampling)
    for (int depth = 0;;) {
        int mi;
        const double t = sampleCollision(ray, rng, c, &mi);
        if (t == NoCollision) {
            double w = 1;
            if (phasePdf > 0 && effects_.nextEvent)
                w = effects_.mis == MisHeuristic::None
                        ? 0.0
                        : misWeight(phasePdf, lightPdf(lobe, ray.d, c));
            if (w > 0) L += beta * w * env.Le(ray.d);
            break;
        }
        if (++depth > s.maxDepth) break;
        ++c.scatteringEvents;
        const Medium& medium = *scene_.media[mi];
        beta *= medium.albedo();
        const Vec3 p = ray(t);
        const PhaseFunction& phase = medium.phase();

        if (effects_.nextEvent) {
            if (product) {
                product_->rotateZonal(lobes_[mi].p.data(), ray.d, lobe.lobe, lobes_[mi].bands);
                lobe.beta = lobes_[mi].beta;
            }
            ++c.lightSamples;
            const LightDraw ls = sampleLight(lobe, sampler.next2D(), c);
            if (ls.pdf > 0 && ls.Le.maxCoeff() > 0) {
                const double f = phase.eval(ray.d, ls.wi);
                if (f > 0) {
                    const double T = transmittance(Ray{p, ls.wi}, rng, c);
                    const double w = misWeight(ls.pdf, phase.pdf(ray.d, ls.wi));
                    L += beta * (f * T * w / ls.pdf) * ls.Le;
                }
            }
        }

        ++c.phaseSamples;
        const PhaseSample ps = phase.sample(ray.d, sampler.next2D());
        if (!(ps.pdf > 0) || !(ps.value > 0)) break;
        beta *= ps.value / ps.pdf;
        phasePdf = ps.pdf;
        ray = Ray{p, ps.wi};

        if (depth >= s.rrDepth) {
            // Drawn whether or not it is needed: each bounce takes a fixed set of numbers.
            const double u = sampler.next1D();
            const double q = maxComponent(beta);
            if (q < 1) {
                if (u >= q) break;
                beta /= q;
            }
        }
    }
    return L;
}

template Spectrum VolumePathIntegrator::Li(Ray, Rng&, PathCounters&) const;
template Spectrum VolumePathIntegrator::Li(Ray, SobolSampler&, PathCounters&) const;

}  // namespace shvol
