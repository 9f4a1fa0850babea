#include "shvol/render/volume_path_integrator.h"

namespace shvol {

void PathCounters::add(const PathCounters& o) {
    paths += o.paths;
    scatteringEvents += o.scatteringEvents;
    phaseSamples += o.phaseSamples;
    lightSamples += o.lightSamples;
    transmittanceRays += o.transmittanceRays;
    nonFiniteSamples += o.nonFiniteSamples;
    tracking.densityLookups += o.tracking.densityLookups;
    tracking.segments += o.tracking.segments;
}

VolumePathIntegrator::VolumePathIntegrator(const Scene& scene)
    : scene_(scene), effects_(Effects::of(scene)) {}

double VolumePathIntegrator::sampleCollision(const Ray& ray, Rng& rng, PathCounters& c,
                                             const Medium** medium) const {
    double tHit = NoCollision;
    *medium = nullptr;
    for (const auto& m : scene_.media) {
        // Only collisions before the nearest one found so far matter.
        const double t = m->sampleCollision(ray, tHit, rng, c.tracking);
        if (t < tHit) tHit = t, *medium = m.get();
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

Spectrum VolumePathIntegrator::Li(Ray ray, Rng& rng, PathCounters& c) const {
    ++c.paths;
    const Environment& env = scene_.environment;
    if (!effects_.volumes) return env.Le(ray.d);
    if (!effects_.scattering) return transmittance(ray, rng, c) * env.Le(ray.d);

    const RenderSettings& s = scene_.settings;
    Spectrum L = Spectrum::Zero(), beta = Spectrum::Ones();
    double phasePdf = 0;  // pdf of the phase sample that started this ray; 0 for camera rays
    for (int depth = 0;;) {
        const Medium* medium;
        const double t = sampleCollision(ray, rng, c, &medium);
        if (t == NoCollision) {
            double w = 1;
            if (phasePdf > 0 && effects_.nextEvent) {
                const double pl = env.pdf(ray.d);
                w = phasePdf / (phasePdf + pl);
            }
            L += beta * w * env.Le(ray.d);
            break;
        }
        if (++depth > s.maxDepth) break;
        ++c.scatteringEvents;
        beta *= medium->albedo();
        const Vec3 p = ray(t);
        const PhaseFunction& phase = medium->phase();

        if (effects_.nextEvent) {
            ++c.lightSamples;
            const LightSample ls = env.sample(rng.uniform2());
            if (ls.pdf > 0 && ls.Le.maxCoeff() > 0) {
                const double f = phase.eval(ray.d, ls.wi);
                if (f > 0) {
                    const double T = transmittance(Ray{p, ls.wi}, rng, c);
                    const double w = ls.pdf / (ls.pdf + phase.pdf(ray.d, ls.wi));
                    L += beta * (f * T * w / ls.pdf) * ls.Le;
                }
            }
        }

        ++c.phaseSamples;
        const PhaseSample ps = phase.sample(ray.d, rng.uniform2());
        if (!(ps.pdf > 0) || !(ps.value > 0)) break;
        beta *= ps.value / ps.pdf;
        phasePdf = ps.pdf;
        ray = Ray{p, ps.wi};

        if (depth >= s.rrDepth) {
            const double q = maxComponent(beta);
            if (q < 1) {
                if (rng.uniform() >= q) break;
                beta /= q;
            }
        }
    }
    return L;
}

}  // namespace shvol
