#include "shvol/render/volume_path_integrator.h"

#include <tbb/parallel_for.h>

#include <boost/math/special_functions/gamma.hpp>

#include <algorithm>
#include <chrono>
#include <limits>

#include "shvol/core/error.h"
#include "shvol/phase/sh_sampled_phase.h"
#include "shvol/phase/zonal_fit.h"
#include "shvol/sampling/russian_roulette.h"

namespace shvol {

namespace {
/// All of a direction's components are finite: their sum is (it cannot overflow for a direction,
/// and a NaN or an infinity in any makes it NaN or infinite). Two additions, where Eigen's
/// allFinite took about 10 instructions a scattering event.
bool finiteDirection(const Vec3& w) {
    return std::isfinite(w.x() + w.y() + w.z());
}

/// A sampler's draw that no path can use (InvalidDraws): a NaN or negative pdf or value, or,
/// with a positive pdf, a direction that is not finite. (A pdf of 0 is a draw that found
/// nothing, whatever its direction.)
bool unusableDraw(double pdf, const Vec3& wi, double value = 0) {
    return !(pdf >= 0) || !(value >= 0) || (pdf > 0 && !finiteDirection(wi));
}
}  // namespace

double truncatedShareLowerBound(uint64_t truncated, uint64_t paths) {
    if (truncated == 0 || paths == 0) return 0;
    return boost::math::gamma_p_inv(double(truncated), 0.05) / double(paths);
}

void InvalidDraws::add(const InvalidDraws& o) {
    phase += o.phase;
    bsdf += o.bsdf;
    light += o.light;
    flight += o.flight;
    transmittance += o.transmittance;
}

std::string invalidDrawsWarning(const InvalidDraws& d) {
    if (d.total() == 0) return "";
    std::string text;
    d.forEachSource([&](const char*, const char* words, uint64_t n) {
        if (n > 0) text += (text.empty() ? "" : ", ") + std::to_string(n) + " " + words;
    });
    return std::to_string(d.total()) + " draws of samplers or media were NaN or negative (" + text +
           "): the paths or light samples that met them were dropped, so the image lacks their "
           "light; this is a defect of shvol: please report it with the scene";
}

void PathCounters::add(const PathCounters& o) {
    paths += o.paths;
    scatteringEvents += o.scatteringEvents;
    phaseSamples += o.phaseSamples;
    lightSamples += o.lightSamples;
    productSamples += o.productSamples;
    productPdfs += o.productPdfs;
    transmittanceRays += o.transmittanceRays;
    nonFiniteSamples += o.nonFiniteSamples;
    truncatedPaths += o.truncatedPaths;
    invalid.add(o.invalid);
    surfaceHits += o.surfaceHits;
    cacheLookups += o.cacheLookups;
    cacheHits += o.cacheHits;
    cacheLookupNs += o.cacheLookupNs;
    surfaceEvents += o.surfaceEvents;
    areaLightSamples += o.areaLightSamples;
    shadowRays += o.shadowRays;
    tracking.densityLookups += o.tracking.densityLookups;
    tracking.segments += o.tracking.segments;
    tracking.exactCells += o.tracking.exactCells;
    phaseWeights.add(o.phaseWeights);
}

VolumePathIntegrator::VolumePathIntegrator(const Scene& scene, std::function<bool()> stop)
    : scene_(scene),
      effects_(Effects::of(scene)),
      mediumBit_(scene.media.size(), -1),
      cameraPosition_(scene.camera.position) {
    if (effects_.areaLights) areaLights_ = std::make_unique<const AreaLights>(*scene.surfaces);
    if (scene.surfaces)
        for (const Surface& sf : scene.surfaces->surfaces())
            deltaSurfaces_ |= sf.bsdf.isDeltaScatterer();
    for (const auto& m : scene.media) {
        mediumBounds_.push_back(m->bounds());
        // The weights' compounding is counted where a weight is not always 1 (README, "Phase
        // functions", `evaluate`): the exact use of an SH-sampled phase function (m₂ is exactly 1
        // for the reconstruction's).
        const auto* sh = std::get_if<SHSampledPhase>(&m->phase().variant());
        const bool weighted = sh && sh->weightSecondMoment() > 1;
        phaseLnM2_.push_back(weighted ? std::log(sh->weightSecondMoment()) : 0.0);
        phaseWeights_ |= weighted;
    }
    if (effects_.boundedMedia) {
        const auto& surfaces = scene.surfaces->surfaces();
        for (size_t i = 0; i < surfaces.size(); ++i) {
            const int m = surfaces[i].interiorMedium;
            if (m < 0) continue;
            mediumBit_[m] = int(boundaryOf_.size());
            boundaryOf_.push_back(int(i));
        }
        // (The loader refuses more: Inside is a 64-bit set.)
        if (boundaryOf_.size() > 64) throw Error(scene.path + ": more than 64 bounded media");
        // No shadow ray from inside a closed surface that is not a null one (glass around fog)
        // reaches a light outside it: the sky, or an emitting surface whose bounds do not meet
        // its bounds. (Decided per boundary: one lamp anywhere in the scene unsealed them all,
        // and milk_glass spent 42% of its render on shadow rays that glass stopped; helper 169.)
        // A delta boundary only: a path leaves it by a delta event, after which the light it
        // meets counts whole (prevPdf 0), so no light sample's share of it is lost. (Boundaries
        // are null or dielectric; a rough one would need its light samples.)
        std::vector<Bounds3> lamps;
        for (const Surface& e : surfaces)
            if (e.emits()) lamps.push_back(e.bounds());
        for (size_t b = 0; b < boundaryOf_.size(); ++b) {
            const Surface& boundary = surfaces[boundaryOf_[b]];
            if (!boundary.bsdf.isDeltaScatterer()) continue;
            const Bounds3 inside = boundary.bounds();
            if (std::none_of(lamps.begin(), lamps.end(),
                             [&](const Bounds3& lamp) { return lamp.meets(inside); }))
                sealed_ |= Inside(1) << b;
        }
        cameraInside_ = insideOf(scene.camera.position);
    }
    buildLightSamplers();
    if (!stop) stop = [] { return false; };
    if (effects_.radianceCache) buildRadianceCache(stop);  // record paths use the light samplers
}

void VolumePathIntegrator::buildLightSamplers() {
    if (!effects_.nextEvent) return;
    const auto start = std::chrono::steady_clock::now();
    // An image sky's texel tables, here and not at the first light sample: in the setup's time,
    // not the passes' (nor under their time limit; review of helper 168's change).
    if (effects_.lightSampling == LightSampling::Environment)
        scene_.environment.prepareSampling();
    else
        buildSkySamplers();
    setupSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void VolumePathIntegrator::buildSkySamplers() {
    const Scene& scene = scene_;
    const RenderSettings& s = scene.settings;
    sky_ =
        std::make_unique<const SkyHierarchy>(scene.environment.skyHierarchy(s.waveletCoefficients));
    effects_.skyCompressed = sky_->compressed();
    if (effects_.lightSampling == LightSampling::Product) {
        product_ = std::make_unique<const ProductSampler>(*sky_, s.productOrder, s.productDepth);
        for (const auto& m : scene.media) {
            // The lobe only shapes the pdf: a Hann-windowed fit rings least (zonal_fit.h).
            const PhaseFunction& phase = m->phase();
            const ZonalFit fit = fitZonal([&](const AngleCosine& c) { return phase.evalAngle(c); },
                                          s.productOrder, SHWindow::Hann, phase.corners());
            // Without MIS the product sampler alone must reach every lit direction: the
            // defensive share then guards against cells whose lobe mass rounds to ≤ 0 even for
            // a fit that is non-negative at its quadrature nodes.
            const double beta = effects_.mis == MisHeuristic::None
                                    ? ProductSampler::kDefensiveFraction
                                    : product_->defensiveShare(fit.minValue);
            lobes_.push_back({fit.p, ProductSampler::significantBands(fit.p), beta});
        }
    }
}

VolumePathIntegrator::Inside VolumePathIntegrator::insideAt(const Vec3& p) const {
    return p == cameraPosition_ ? cameraInside_ : insideOf(p);
}

VolumePathIntegrator::Inside VolumePathIntegrator::insideOf(const Vec3& p) const {
    Inside in = 0;
    for (size_t b = 0; b < boundaryOf_.size(); ++b)
        if (scene_.surfaces->inside(boundaryOf_[b], p)) in |= Inside(1) << b;
    return in;
}

VolumePathIntegrator::Inside VolumePathIntegrator::crossed(const SurfaceHit& hit, const Vec3& d,
                                                           Inside inside) const {
    const int m = scene_.surfaces->surfaces()[hit.surface].interiorMedium;
    if (m < 0) return inside;
    const Inside bit = Inside(1) << mediumBit_[m];
    return d.dot(hit.ng) < 0 ? inside | bit : inside & ~bit;
}

namespace {
/// Counts a flight distance no path can use (NaN or negative) and ends the path (NaN): the cold
/// branch of sampleCollision, out of line.
[[gnu::cold, gnu::noinline]] double invalidFlight(PathCounters& c, int* medium) {
    ++c.invalid.flight;
    *medium = -1;
    return NAN;
}
}  // namespace

// (Inlined into Li: out of line, its call cost about 2% of the plume's instructions.)
__attribute__((always_inline)) inline double VolumePathIntegrator::sampleCollision(
    const Ray& ray, double tMax, Inside inside, Rng& rng, const DeferredPair& first,
    PathCounters& c, int* medium) const {
    double tHit = tMax;
    *medium = -1;
    // The pair for the first medium the ray meets; the others' flights are independent.
    const DeferredPair* pending = &first;
    Vec2 u;
    for (size_t i = 0; i < scene_.media.size(); ++i) {
        // Only collisions before the nearest one found so far matter.
        if (!active(i, inside) || !meets(i, ray, tHit)) continue;
        if (pending) u = pending->value();
        const double t =
            scene_.media[i]->sampleCollision(ray, tHit, rng, c.tracking, pending ? &u : nullptr);
        pending = nullptr;
        if (t < tHit) tHit = t, *medium = int(i);
        if (!(t >= 0)) return invalidFlight(c, medium);  // (NaN or negative)
    }
    return *medium < 0 ? NoCollision : tHit;
}

double VolumePathIntegrator::transmittance(const Ray& ray, double tMax, Inside inside, Rng& rng,
                                           PathCounters& c,
                                           std::optional<TransmittanceEstimator> est) const {
    ++c.transmittanceRays;
    double T = 1;
    for (size_t i = 0; i < scene_.media.size(); ++i) {
        if (!active(i, inside) || !meets(i, ray, tMax)) continue;
        const double Ti = scene_.media[i]->transmittance(
            ray, tMax, est.value_or(scene_.settings.transmittance), rng, c.tracking);
        if (!(Ti >= 0)) {
            ++c.invalid.transmittance;
            return 0;
        }
        T *= Ti;
        if (T <= 0) return 0;
    }
    return T;
}

double VolumePathIntegrator::visibility(const Vec3& x, const Vec3& ng, const LightDraw& ls,
                                        Inside inside, Rng& rng, PathCounters& c) const {
    const SurfaceScene* surf = scene_.surfaces.get();
    if (!surf) return effects_.volumes ? transmittance(Ray{x, ls.wi}, NoHit, inside, rng, c) : 1;
    Ray ray = ng.squaredNorm() > 0 ? surf->spawn(x, ng, ls.wi) : Ray{x, ls.wi};
    const bool toPoint = ls.dist < NoHit;
    double T = 1;
    for (int crossings = 0;; ++crossings) {
        // Towards an emitter's point: aimed at the point moved off its surface, so that it does
        // not occlude itself (SurfaceScene::rayTo).
        double tMax = NoHit;
        if (toPoint) ray = surf->rayTo(ray.o, ls.y, ls.ny, &tMax);
        ++c.shadowRays;
        SurfaceHit hit;
        if (!surf->hasNullSurfaces()) {
            if (surf->occluded(ray, tMax)) return 0;
        } else if (surf->intersect(ray, tMax, &hit)) {
            SurfaceScene::NullCrossings nulls;
            if (surf->resolveCrossing(ray, tMax, &hit, &nulls) || crossings >= kMaxNullCrossings)
                return 0;
            if (effects_.volumes) T *= transmittance(ray, hit.t, inside, rng, c);
            if (T <= 0) return 0;
            for (int k = 0; k < nulls.count; ++k) inside = crossed(nulls.hit[k], ray.d, inside);
            ray = surf->spawn(hit, ray.d);
            continue;
        }
        return effects_.volumes ? T * transmittance(ray, tMax, inside, rng, c) : T;
    }
}

double VolumePathIntegrator::misWeight(double pa, double pb) const {
    if (effects_.mis == MisHeuristic::None) return 1;
    // Written in the ratio r = p_b/p_a so that neither tiny pdfs (squares underflowing to 0/0)
    // nor huge ones (g → 1) can make the weight NaN; pa = 0 gives 0, pb = 0 or ∞ gives 1 or 0.
    if (!(pa > 0)) return 0;
    const double r = pb / pa;
    return effects_.mis == MisHeuristic::Power ? 1 / (1 + r * r) : 1 / (1 + r);
}

double VolumePathIntegrator::environmentShare() const {
    if (!effects_.nextEvent) return 0;
    return effects_.areaLights ? 0.5 : 1;
}

VolumePathIntegrator::LightDraw VolumePathIntegrator::sampleEnvironment(Vertex v,
                                                                        const EventLobe& lobe,
                                                                        const Vec2& u,
                                                                        PathCounters& c) const {
    const Environment& env = scene_.environment;
    WarpSample s;
    LightSampling strategy = effects_.lightSampling;
    if (v == Vertex::Surface && strategy == LightSampling::Product)
        strategy = LightSampling::Wavelet;
    switch (strategy) {
        case LightSampling::Environment: {
            const LightSample ls = env.sample(u);
            return {ls.wi, ls.Le, ls.pdf};
        }
        case LightSampling::Wavelet:
            s = sky_->warp(u);
            break;
        case LightSampling::Product:
            ++c.productSamples;
            s = product_->warp(lobe.lobe, lobe.beta, u);
            break;
    }
    // (A NaN pdf is passed on, to be counted: InvalidDraws. A negative one stays a failed draw,
    // as the samplers' own failed branches are.)
    if (!(s.pdf > 0)) return {Vec3(0, 0, 1), Spectrum::Zero(), std::isnan(s.pdf) ? s.pdf : 0.0};
    const Vec3 w = s.direction();
    return {w, env.Le(w), s.pdf};
}

double VolumePathIntegrator::environmentPdf(Vertex v, const EventLobe& lobe, const Vec3& w,
                                            PathCounters& c) const {
    double pdf;
    switch (effects_.lightSampling) {
        case LightSampling::Wavelet:
            pdf = sky_->pdf(w);
            break;
        case LightSampling::Product:
            if (v == Vertex::Surface) {
                pdf = sky_->pdf(w);
                break;
            }
            ++c.productPdfs;
            pdf = product_->pdf(lobe.lobe, lobe.beta, w);
            break;
        default:
            pdf = scene_.environment.pdf(w);
    }
    return environmentShare() * pdf;
}

template <typename Sampler>
VolumePathIntegrator::LightDraw VolumePathIntegrator::sampleLights(const Vec3& x, Vertex v,
                                                                   const EventLobe& lobe,
                                                                   Sampler& sampler,
                                                                   PathCounters& c) const {
    ++c.lightSamples;
    double uSelect = effects_.areaLights ? sampler.next1D() : 0;
    const Vec2 u = sampler.next2D();
    const double pEnv = environmentShare();
    if (uSelect < pEnv) {
        LightDraw ls = sampleEnvironment(v, lobe, u, c);
        ls.pdf *= pEnv;
        return usableLightDraw(ls, c);
    }
    ++c.areaLightSamples;
    uSelect = std::min((uSelect - pEnv) / (1 - pEnv), std::nextafter(1.0, 0.0));
    const AreaLightSample as = areaLights_->sample(x, uSelect, u);
    return usableLightDraw({as.wi, as.Le, as.pdf * (1 - pEnv), as.dist, as.y, as.ny}, c);
}

LightSample VolumePathIntegrator::sampleLightsAtSurface(const Vec3& x, Rng& rng) const {
    PathCounters c;
    const LightDraw d = sampleLights(x, Vertex::Surface, EventLobe{}, rng, c);
    return {d.wi, d.Le, d.pdf};
}

void VolumePathIntegrator::setEventLobe(size_t medium, const Vec3& d, EventLobe& lobe) const {
    product_->rotateZonal(lobes_[medium].p.data(), d, lobe.lobe, lobes_[medium].bands);
    lobe.beta = lobes_[medium].beta;
}

LightSample VolumePathIntegrator::sampleLightsInMedium(const Vec3& x, const Vec3& d, size_t medium,
                                                       Rng& rng) const {
    PathCounters c;
    EventLobe lobe;
    if (product_) setEventLobe(medium, d, lobe);
    const LightDraw draw = sampleLights(x, Vertex::Medium, lobe, rng, c);
    return {draw.wi, draw.Le, draw.pdf};
}

double VolumePathIntegrator::environmentPdfInMedium(const Vec3& d, size_t medium,
                                                    const Vec3& w) const {
    PathCounters c;
    EventLobe lobe;
    if (product_) setEventLobe(medium, d, lobe);
    return environmentPdf(Vertex::Medium, lobe, w, c);
}

VolumePathIntegrator::LightDraw VolumePathIntegrator::usableLightDraw(LightDraw ls,
                                                                      PathCounters& c) {
    if (unusableDraw(ls.pdf, ls.wi) || (ls.pdf > 0 && !(ls.Le >= 0).all())) {
        ++c.invalid.light;
        ls.pdf = 0;
    }
    return ls;
}

template <typename Sampler>
Spectrum VolumePathIntegrator::Li(Ray ray, Sampler& sampler, PathCounters& c, PathKind kind) const {
    Rng& rng = sampler.rng();
    ++c.paths;
    const Environment& env = scene_.environment;
    const SurfaceScene* surf = scene_.surfaces.get();
    if (!surf) {
        if (!effects_.volumes) return env.Le(ray.d);
        if (!effects_.scattering) {
            // (No transmittance for a ray that meets no light: below a black lower hemisphere
            // it was 65% of an absorbing cloud's render; helper 168.)
            const Spectrum Le = env.Le(ray.d);
            return (Le > 0).any() ? Spectrum(transmittance(ray, NoHit, 0, rng, c) * Le) : Le;
        }
    }

    const RenderSettings& s = scene_.settings;
    const bool product = product_ != nullptr;
    const bool nee = effects_.anyNextEvent();
    Inside inside = effects_.boundedMedia ? insideAt(ray.o) : 0;
    Spectrum L = Spectrum::Zero(), beta = Spectrum::Ones();
    // The vertex that started this ray: the density with which it sampled the ray's direction
    // (0 for the camera and delta lobes: no MIS), its position and kind.
    double prevPdf = 0;
    Vec3 prevP = ray.o;
    Vertex prevVertex = Vertex::Medium;
    EventLobe lobe;    // the last scattering event's lobe (product sampling)
    double lnM2k = 0;  // Σ ln m₂ of the SH-sampled phase weights so far (phaseWeights_)
    // Π η² over the refractions so far: β·etaScale is the throughput the roulette judges, as β
    // alone falls by 1/η² on entering glass (radiance, not energy, is scaled) and rises again
    // on leaving it. Judged on β, the roulette killed paths inside glass for a loss that is not
    // one (in a white furnace of albedo-1 fog in a glass sphere, samples of 0 and 2.25 among
    // the 1s).
    double etaScale = 1;
    int nullCrossings = 0;
    // After a cached vertex the path goes one ray further only for the direct light its BSDF
    // sample meets (directOnly): at the end of that ray (chainMis: with next-event estimation
    // and MIS, outside sealed media), MIS-weighted against the lightCount light samples drawn
    // there, and wherever it arrives through mirrors and glass alone (afterDelta), which no light
    // sample reaches, with weight 1.
    bool directOnly = false, chainMis = false, afterDelta = false;
    double lightCount = 1;
    bool scattered = false;
    const bool record = kind == PathKind::CacheRecord;
    // A record path of the radiance cache leaves out the light that the cached vertex it serves
    // takes itself: what its next-event estimation adds, and the light it reaches through
    // mirrors and glass alone. Records held that light, a caustic, for every point each serves,
    // and a mirror's lamp light came out 1.2% dark on a floor beside it (helper 134). So until
    // its first scattering event that is not a delta one.
    bool recordLeavesOut = record;
    // A record path continues a camera path from its first vertex: it starts one bounce deep,
    // so that cached pixels see at most max_depth bounces too.
    for (int depth = record ? 1 : 0;;) {
        SurfaceHit hit;
        SurfaceScene::NullCrossings nulls;  // (crossed at the hit, coincident within ε)
        const bool hitSurface = surf && surf->intersect(ray, NoHit, &hit);
        if (hitSurface && surf->hasNullSurfaces()) surf->resolveCrossing(ray, NoHit, &hit, &nulls);
        int mi = -1;
        double t = NoCollision;
        if (effects_.volumes && anyActive(inside)) {
            const double tHit = hitSurface ? hit.t : NoHit;
            if (directOnly) {
                // (Light that would not count, at the end of a ray that no mirror or glass takes
                // further: no transmittance to estimate.)
                if (!chainMis && !afterDelta &&
                    !(hitSurface && surf->surfaces()[hit.surface].bsdf.isDelta()))
                    break;
                // Only the light at the ray's end counts: the media's transmittance as a shadow
                // ray estimates it, not a free flight's all-or-nothing (in absorbing fog about a
                // lamp the image spread 3× as much between seeds as with light samples alone;
                // helper 121).
                const double T = transmittance(ray, tHit, inside, rng, c);
                if (!(T > 0)) break;
                beta *= T;
            } else {
                const DeferredPair uFlight = deferred2D(sampler);
                t = sampleCollision(ray, tHit, inside, rng, uFlight, c, &mi);
                if (std::isnan(t)) break;  // (counted)
            }
        }
        if (t == NoCollision && !hitSurface) {
            double w = 1;
            if (prevPdf > 0 && effects_.nextEvent)
                w = effects_.mis == MisHeuristic::None
                        ? 0.0
                        : misWeight(prevPdf,
                                    lightCount * environmentPdf(prevVertex, lobe, ray.d, c));
            // (a sky not light-sampled is the cache's, which its records met, but through mirrors
            // and glass alone)
            if (directOnly && !afterDelta && !(chainMis && effects_.nextEvent)) w = 0;
            if (w > 0 && !(recordLeavesOut && (afterDelta || effects_.nextEvent)))
                L += beta * w * env.Le(ray.d);
            break;
        }
        if (t == NoCollision) {  // the surface
            ++c.surfaceHits;
            const Surface& sf = surf->surfaces()[hit.surface];
            // The light of the surface hit, and of null ones met at the same place (an invisible
            // light on a fog box's face: the one Embree did not report was jumped, dark).
            const auto addEmitted = [&](const SurfaceHit& h) {
                const Surface& e = surf->surfaces()[h.surface];
                if (!e.emits() || (recordLeavesOut && (afterDelta || effects_.areaLights))) return;
                // (the cache's, as the sky's)
                if (directOnly && !afterDelta && !(chainMis && effects_.areaLights)) return;
                const Spectrum Le = e.Le(h.ng, -ray.d);
                double w = 1;
                if (prevPdf > 0 && effects_.areaLights)
                    w = effects_.mis == MisHeuristic::None
                            ? 0.0
                            : misWeight(prevPdf, lightCount * (1 - environmentShare()) *
                                                     areaLights_->pdf(prevP, h.surface, h.p, h.ng));
                if (w > 0) L += beta * w * Le;
            };
            addEmitted(hit);
            for (int k = 0; k < nulls.count; ++k)
                if (nulls.hit[k].surface != hit.surface) addEmitted(nulls.hit[k]);
            const Bsdf& bsdf = sf.bsdf;
            if (bsdf.type == BsdfType::Null) {
                if (++nullCrossings > kMaxNullCrossings) break;
                for (int k = 0; k < nulls.count; ++k) inside = crossed(nulls.hit[k], ray.d, inside);
                ray = surf->spawn(hit, ray.d);
                continue;
            }
            // (through delta surfaces the direct light goes on: no light sample reaches it there)
            if (directOnly && !bsdf.isDelta()) break;
            if (++depth > s.maxDepth) {
                ++c.truncatedPaths;
                break;
            }
            nullCrossings = 0;  // (the guard is per ray)
            ++c.surfaceEvents;
            const Frame frame =
                bsdf.anisotropic() ? Frame(hit.ns, sf.tangent, sf.tangentY) : Frame(hit.ns);
            const Vec3 wo = frame.toLocal(-ray.d);
            const double cosOg = -ray.d.dot(hit.ng);
            // A camera path's first scattering vertex: the cache answers for the indirect light,
            // next-event estimation and one BSDF sample, MIS-weighted, for the direct light (with
            // `mis: "none"`, light samples alone, weight 1), and the path ends once the BSDF
            // sample has met its light.
            Spectrum cached;
            const bool fromCache = kind == PathKind::Camera && !scattered && cache_ &&
                                   tables_[hit.surface] && cachedRadiance(hit, -ray.d, &cached, c);
            // A cached vertex ends the path, so its direct light can afford several samples.
            const int lightSamples = fromCache ? s.radianceCache.lightSamples : 1;
            const bool cacheMis = fromCache && effects_.mis != MisHeuristic::None;
            for (int k = 0; nee && !sealed(inside) && !bsdf.isDelta() && k < lightSamples; ++k) {
                const LightDraw ls = sampleLights(hit.p, Vertex::Surface, lobe, sampler, c);
                // Reflection stays on the side it came from, judged by the geometric normal too,
                // so that shading normals cannot leak light through a surface.
                if (ls.pdf > 0 && ls.Le.maxCoeff() > 0 &&
                    (bsdf.transmits() || ls.wi.dot(hit.ng) * cosOg > 0)) {
                    const Vec3 wi = frame.toLocal(ls.wi);
                    const Spectrum f = bsdf.eval(wo, wi) * std::abs(wi.z());
                    if (!(f >= 0).all())
                        ++c.invalid.bsdf;
                    else if (f.maxCoeff() > 0) {
                        const double T = visibility(hit.p, hit.ng, ls, inside, rng, c);
                        if (T > 0) {
                            // (n light samples and one BSDF sample: the heuristic of n·p_light,
                            // Veach 1997 §9.2.2, over the n samples)
                            const double w =
                                fromCache && !cacheMis
                                    ? 1.0 / lightSamples
                                    : misWeight(lightSamples * ls.pdf, bsdf.pdf(wo, wi)) /
                                          lightSamples;
                            L += beta * f * (T * w / ls.pdf) * ls.Le;
                        }
                    }
                }
            }
            if (fromCache) {
                L += beta * cached;
                // Light samples alone had an unbounded weight by a corner, where the light's
                // solid-angle density falls as r² (a furnace box's mean was 4% from seed to
                // seed, +13.7% at worst of 16; helper 119).
                chainMis = cacheMis && nee && !sealed(inside);
                if (!chainMis && !deltaSurfaces_) break;
                directOnly = true;
                lightCount = lightSamples;
            }
            scattered = true;
            if (bsdf.isDelta())
                afterDelta = true;
            else
                recordLeavesOut = false;
            const std::optional<BsdfSample> bs = bsdf.sample(wo, sampler.next2D());
            if (!bs) break;
            if (!(bs->pdf > 0) || !finiteDirection(bs->wi) || !(bs->f >= 0).all()) {
                if (unusableDraw(bs->pdf, bs->wi) || !(bs->f >= 0).all()) ++c.invalid.bsdf;
                break;
            }
            const Vec3 wi = frame.toWorld(bs->wi);
            const bool transmitted = wi.dot(hit.ng) * cosOg < 0;
            if (transmitted && !bsdf.transmits()) break;
            beta *= bs->f * (std::abs(bs->wi.z()) / bs->pdf);
            // The BSDF scales radiance by the η of the crossing it chose in the shading frame;
            // the path is in the region the geometric normal says (crossed()). Near a silhouette
            // of interpolated normals the two disagree, and the 1/η² of entering glass went
            // unpaired with the η² of leaving it (albedo-1 fog in a smooth-shaded glass mesh under
            // a constant sky: samples of 0.44 and 2.25 among the 1s, a mean 10σ below 1). The
            // radiance scale is the geometric crossing's (ior is 1 for all but dielectrics).
            const double eta = !transmitted ? 1.0 : ray.d.dot(hit.ng) < 0 ? bsdf.ior : 1 / bsdf.ior;
            beta *= (bs->eta / eta) * (bs->eta / eta);
            etaScale *= eta * eta;
            prevPdf = bs->delta ? 0 : bs->pdf;
            prevP = hit.p;
            prevVertex = Vertex::Surface;
            if (transmitted) inside = crossed(hit, wi, inside);
            // Through a null surface met at the same place, within ε (fog in a glass tank, its
            // null box on the tank's inner wall): its medium is entered or left too (it stayed
            // outside). Reflected, the path stays on the side it came from.
            if (transmitted && nulls.count == 0 && surf->hasNullSurfaces())
                surf->nullsAt(ray, hit, &nulls);
            for (int k = 0; k < nulls.count; ++k)
                if (wi.dot(nulls.hit[k].ng) * ray.d.dot(nulls.hit[k].ng) > 0)
                    inside = crossed(nulls.hit[k], ray.d, inside);
            ray = surf->spawn(hit, wi);
        } else {  // a real collision in media[mi]
            if (++depth > s.maxDepth) {
                if (scene_.media[mi]->scatters()) ++c.truncatedPaths;  // (absorbed: nothing lost)
                break;
            }
            nullCrossings = 0;
            ++c.scatteringEvents;
            if (phaseWeights_) lnM2k += phaseLnM2_[mi];
            const Medium& medium = *scene_.media[mi];
            beta *= medium.albedo();
            if (!(beta.maxCoeff() > 0)) break;
            scattered = true;
            recordLeavesOut = false;
            // (Within ε of the surface ahead: ε off it, as after a surface event.)
            const Vec3 p = hitSurface ? surf->offSurfaceAhead(ray(t), hit, ray.d) : ray(t);
            const PhaseFunction& phase = medium.phase();

            if (nee && !sealed(inside)) {
                if (product) setEventLobe(mi, ray.d, lobe);
                const LightDraw ls = sampleLights(p, Vertex::Medium, lobe, sampler, c);
                if (ls.pdf > 0 && ls.Le.maxCoeff() > 0) {
                    const double f = phase.eval(ray.d, ls.wi);
                    if (!(f >= 0)) ++c.invalid.phase;
                    if (f > 0) {
                        const double T = visibility(p, Vec3::Zero(), ls, inside, rng, c);
                        const double w = misWeight(ls.pdf, phase.pdf(ray.d, ls.wi));
                        L += beta * (f * T * w / ls.pdf) * ls.Le;
                    }
                }
            }

            ++c.phaseSamples;
            const PhaseSample ps = phase.sample(ray.d, sampler.next2D());
            if (!(ps.pdf > 0) || !(ps.value > 0) || !finiteDirection(ps.wi)) {
                if (unusableDraw(ps.pdf, ps.wi, ps.value)) ++c.invalid.phase;
                break;
            }
            beta *= ps.value / ps.pdf;
            prevPdf = ps.pdf;
            prevP = p;
            prevVertex = Vertex::Medium;
            ray = Ray{p, ps.wi};
        }

        if (depth >= s.rrDepth) {
            // The roulette's number: with next-event estimation (towards the sky or area lights)
            // the roulette is on the throughput (θ = 1) and plays at nearly every bounce, and a
            // Sobol' request of its own every bounce keeps it stratified (from the independent
            // stream, as below, the RMSE of the NEE sweeps of validation/sampling rose 2–10%:
            // helper 79). Without NEE the survival weight (θ = 0.25) rarely plays it: then the
            // independent stream, only when needed (a request every bounce did not lower the
            // error and cost up to 3% of the time; README, "Sample streams").
            const double q =
                rouletteSurvival(maxComponent(beta) * etaScale, effects_.rouletteThreshold);
            const double u = nee ? sampler.next1D() : q < 1 ? rng.uniform() : 0;
            if (q < 1) {
                if (u >= q) break;
                beta /= q;
            }
        }
    }
    if (phaseWeights_ && kind == PathKind::Camera) c.phaseWeights.add(lnM2k);
    return L;
}

template Spectrum VolumePathIntegrator::Li(Ray, Rng&, PathCounters&, PathKind) const;
template Spectrum VolumePathIntegrator::Li(Ray, SobolSampler&, PathCounters&, PathKind) const;

namespace {
/// The radiance cache's normals at a hit seen from wo. n, the frame of records and BRDF tables:
/// the shading normal on wo's side, the hemisphere the two-sided BSDF reflects into (its frame
/// is the shading normal's in Li too), so smooth meshes shade indirect light smoothly. ng: the
/// geometric normal on wo's side, below whose plane light is refused.
struct CacheNormals {
    Vec3 n, ng;
};
CacheNormals cacheNormals(const SurfaceHit& hit, const Vec3& wo) {
    return {hit.ns.dot(wo) >= 0 ? hit.ns : Vec3(-hit.ns),
            hit.ng.dot(wo) >= 0 ? hit.ng : Vec3(-hit.ng)};
}
}  // namespace

bool VolumePathIntegrator::cachedRadiance(const SurfaceHit& hit, const Vec3& wo, Spectrum* L,
                                          PathCounters& c) const {
    const auto start = std::chrono::steady_clock::now();
    ++c.cacheLookups;
    const auto [n, ng] = cacheNormals(hit, wo);
    const int nn = cache_->order() * cache_->order();
    thread_local std::vector<double> lambda, coefficients;
    lambda.resize(3 * nn);
    coefficients.resize(3 * nn);
    const bool found = cache_->lookup(hit.p, n, ng, lambda.data());
    if (found) {
        ++c.cacheHits;
        const Surface& sf = scene_.surfaces->surfaces()[hit.surface];
        tables_[hit.surface]->coefficients(Frame(n), Frame(n, sf.tangent, sf.tangentY), wo,
                                           coefficients.data());
        for (int k = 0; k < 3; ++k) {
            double sum = 0;
            for (int i = 0; i < nn; ++i) sum += lambda[k * nn + i] * coefficients[k * nn + i];
            // Truncated HSH series and extrapolation by gradients can ring below zero near
            // corners; radiance cannot (a clamp, so the cache's bias includes it).
            (*L)[k] = std::max(0.0, sum);
        }
    }
    c.cacheLookupNs += uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                    std::chrono::steady_clock::now() - start)
                                    .count());
    return found;
}

namespace {
/// A stretch of walkToSolid that asks nothing of the media it crosses.
constexpr auto throughMedia = [](const Ray&, double, auto) { return true; };
}  // namespace

template <typename Stretch>
bool VolumePathIntegrator::walkToSolid(Ray ray, Stretch&& stretch, SurfaceHit* end) const {
    const SurfaceScene& surf = *scene_.surfaces;
    Inside inside = effects_.boundedMedia ? insideAt(ray.o) : 0;
    for (int k = 0; k <= kMaxNullCrossings; ++k) {
        SurfaceHit hit;
        SurfaceScene::NullCrossings nulls;
        const bool hitSurface = surf.intersect(ray, NoHit, &hit);
        const bool solid = hitSurface && surf.resolveCrossing(ray, NoHit, &hit, &nulls);
        if (effects_.volumes && anyActive(inside) &&
            !stretch(ray, hitSurface ? hit.t : NoHit, inside))
            return false;
        if (!hitSurface) return false;
        if (solid) {
            *end = hit;
            return true;
        }
        for (int j = 0; j < nulls.count; ++j) inside = crossed(nulls.hit[j], ray.d, inside);
        ray = surf.spawn(hit, ray.d);
    }
    return false;
}

bool VolumePathIntegrator::firstMet(const Ray& ray, Rng& rng, Vec3* W, Vec3* nW) const {
    PathCounters c;  // (a flight no path can use is counted where Li meets it)
    int medium = -1;
    Vec3 collision;
    double depth = 0;  // σ_t at the collision × its distance from the ray's origin
    SurfaceHit end;
    bool solid = walkToSolid(
        ray,
        [&](const Ray& r, double tMax, Inside inside) {
            const double t = sampleCollision(r, tMax, inside, rng, deferred2D(rng), c, &medium);
            if (medium >= 0)
                collision = r(t),
                depth = scene_.media[medium]->sigmaT(collision) * (collision - ray.o).norm();
            return medium < 0;
        },
        &end);
    if (medium >= 0) {
        // Whether the media hide what lies behind them: the collision is farther than a mean free
        // path there (nearer ones, in a deep fog, ruled R's harmonic mean and made records by
        // the thousand: a Cornell box filled with fog of optical depth 8 across made 3844
        // records for 785 and answered 39 lookups for 553, with no gain where it was measured),
        // and the media's transmittance along the whole ray (asked only of such rays) is small.
        double T = 1;
        const auto dim = [&](const Ray& r, double tMax, Inside inside) {
            // (Ratio tracking whatever render.transmittance says: a delta-tracked estimate is 0
            // or 1, and "delta" doubled the records of a fog; helper 109. Its roulette below 0.1
            // makes the cut at 0.1 soft: a T of 0.05 is called opaque half the time.)
            T *= transmittance(r, tMax, inside, rng, c, TransmittanceEstimator::Ratio);
            return T > 0;
        };
        solid = depth >= 1 ? walkToSolid(ray, dim, &end) : walkToSolid(ray, throughMedia, &end);
        if (depth >= 1 && T < kOpaqueTransmittance) {
            *W = collision, *nW = -ray.d;
            return true;
        }
        // (A walk stopped by T = 0 is opaque.)
    }
    if (!solid) return false;
    *W = end.p, *nW = end.ng;
    return true;
}

double VolumePathIntegrator::directIrradiance(const SurfaceHit& hit, const Vec3& n, Rng rng) {
    if (!effects_.anyNextEvent()) return 0;
    constexpr int kSamples = 16;
    PathCounters c;
    double E = 0;
    for (int k = 0; k < kSamples; ++k) {
        const LightDraw ls = sampleLights(hit.p, Vertex::Surface, EventLobe{}, rng, c);
        const double cosine = ls.wi.dot(n);
        if (!(ls.pdf > 0) || !(cosine > 0) || !(ls.wi.dot(hit.ng) * n.dot(hit.ng) > 0)) continue;
        const Ray r = scene_.surfaces->spawn(hit, ls.wi);
        const Inside inside = effects_.boundedMedia ? insideAt(r.o) : 0;
        E += ls.Le.mean() * visibility(r.o, Vec3::Zero(), ls, inside, rng, c) * cosine / ls.pdf;
    }
    cacheBuild_.counters.invalid.add(c.invalid);  // (dropped draws are counted, as elsewhere)
    return E / kSamples;
}

void VolumePathIntegrator::buildRadianceCache(const std::function<bool()>& stop) {
    const RadianceCacheSettings& rc = scene_.settings.radianceCache;
    const SurfaceScene& surf = *scene_.surfaces;
    auto start = std::chrono::steady_clock::now();
    // Every table computed, the rejected ones too: a later surface of the same lobes shares its
    // projections (HshBrdfTable::sameLobes), and is rejected as it was.
    std::vector<std::pair<const Bsdf*, std::shared_ptr<const HshBrdfTable>>> built;
    for (const Surface& s : surf.surfaces()) {
        // (stopped: the rest get no table, and the fill below makes no record)
        const bool cached = HshBrdfTable::supports(s.bsdf) && !stop();
        tables_.push_back(nullptr);
        if (!cached) continue;
        const auto same = std::find_if(built.begin(), built.end(), [&](const auto& b) {
            return HshBrdfTable::sameLobes(*b.first, s.bsdf);
        });
        const bool shared = same != built.end();
        tables_.back() = shared ? std::make_shared<const HshBrdfTable>(*same->second, s.bsdf)
                                : std::make_shared<const HshBrdfTable>(s.bsdf, rc.hshOrder);
        if (!shared) built.emplace_back(&s.bsdf, tables_.back());
        // A lobe the table does not hold is path traced: cached, it came out black or several
        // times too bright.
        if (const double e = tables_.back()->albedoError(); e > kMaxTableAlbedoError) {
            cacheBuild_.uncached.emplace_back(s.name, e);
            tables_.back() = nullptr;
            continue;
        }
        // (shared projections counted once; a table's own part is its n² diffuse coefficients)
        cacheBuild_.tableBytes += shared ? sizeof(double) * size_t(rc.hshOrder * rc.hshOrder)
                                         : tables_.back()->memoryBytes();
        cacheBuild_.tableErrors.push_back(
            {s.name, tables_.back()->projectionError(), tables_.back()->peakError()});
    }
    auto now = std::chrono::steady_clock::now();
    cacheBuild_.tableSeconds = std::chrono::duration<double>(now - start).count();
    start = now;
    cache_ = std::make_unique<RadianceCache>(rc.hshOrder, rc.accuracy, surf.lower(), surf.upper());

    const Camera::Frame camera = scene_.camera.frame();
    const uint64_t seed = scene_.settings.seed;
    const int N = rc.raysPerRecord;
    std::vector<IncomingSample> samples(N);
    std::vector<PathCounters> counters(N);
    // Pixel centres coarse to fine: every 16th pixel, then the new ones of every 8th, ….
    const auto fill = [&] {
        for (int stride = 16; stride >= 1 && int(cache_->size()) < rc.maxRecords; stride /= 2)
            for (int y = 0; y < scene_.camera.height; y += stride)
                for (int x = 0; x < scene_.camera.width; x += stride) {
                    if (stop()) return;
                    if (stride < 16 && x % (2 * stride) == 0 && y % (2 * stride) == 0) continue;
                    if (int(cache_->size()) >= rc.maxRecords) break;
                    // The first surface seen through the pixel centre, past null surfaces (and
                    // through media: a record is made wherever a camera path can reach).
                    const Ray ray = camera.generateRay(x + 0.5, y + 0.5);
                    SurfaceHit hit;
                    if (!walkToSolid(ray, throughMedia, &hit) || !tables_[hit.surface]) continue;
                    const double cosOg = -ray.d.dot(hit.ng);
                    const auto [n, ng] = cacheNormals(hit, -ray.d);
                    if (cosOg == 0 || cache_->covers(hit.p, n, ng)) continue;
                    const uint64_t index = cache_->size();
                    Rng jitterRng = Rng::forSample(seed, (uint64_t(1) << 40) + index, 0);
                    std::vector<Vec2> jitter(N);
                    for (Vec2& u : jitter) u = jitterRng.uniform2();
                    const std::vector<Vec3> dirs = RadianceCache::directions(N, jitter);
                    const Frame frame(n);
                    tbb::parallel_for(0, N, [&](int k) {
                        const Vec3 w = frame.toWorld(dirs[k]);
                        counters[k] = PathCounters{};
                        IncomingSample& sample = samples[k];
                        sample = IncomingSample{};
                        sample.w = dirs[k];
                        // Where the shading hemisphere dips below the surface: no light, as the
                        // path tracer's rule that reflection stays on the side it came from gives.
                        if (!(w.dot(hit.ng) * cosOg > 0)) {
                            sample.L = Spectrum::Zero();
                            sample.below = true;
                            return;
                        }
                        const Ray r = surf.spawn(hit, w);
                        Rng rng =
                            Rng::forSample(seed, (uint64_t(1) << 40) + index, uint32_t(k + 1));
                        sample.L = Li(r, rng, counters[k], PathKind::CacheRecord);
                        // (counted: it was taken as 0 without a word; helper 82)
                        if (!sample.L.allFinite())
                            sample.L = Spectrum::Zero(), ++counters[k].nonFiniteSamples;
                        // What the ray meets first (for R, the walls and the gradients).
                        Rng metRng =
                            Rng::forSample(seed, (uint64_t(1) << 40) + index, uint32_t(N + 2 + k));
                        sample.hit = firstMet(r, metRng, &sample.W, &sample.nW);
                    });
                    for (const PathCounters& pc : counters) cacheBuild_.counters.add(pc);
                    const double direct = directIrradiance(
                        hit, n, Rng::forSample(seed, (uint64_t(1) << 40) + index, uint32_t(N + 1)));
                    cacheBuild_.recordErrors.push_back(
                        float(irradianceRelativeError(samples, direct)));
                    cache_->add(hit.p, n, ng, samples);
                }
    };
    fill();
    cacheBuild_.fillSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace shvol
