#include "shvol/render/effects.h"

#include <cmath>

#include "shvol/cache/hsh_brdf_table.h"
#include "shvol/render/scene.h"

namespace shvol {

bool emissionSurrounds(const Scene& scene) {
    // (An orthographic camera's rays start all over its film, not at one point.)
    if (!scene.surfaces || scene.camera.type != Camera::Type::Perspective) return false;
    const std::vector<Surface>& surfaces = scene.surfaces->surfaces();
    const Surface* emitter = nullptr;
    for (const Surface& s : surfaces)
        if (s.emits()) {
            if (emitter && (s.emission != emitter->emission).any()) return false;
            emitter = &s;
        }
    if (!emitter) return false;
    std::vector<Vec3> origins{scene.camera.position};
    for (const auto& m : scene.media) {
        const Bounds3 b = m->bounds();
        if (!b.empty() && b.lo.allFinite() && b.hi.allFinite())
            origins.push_back(0.5 * (b.lo + b.hi));
    }
    // A ray crosses at most this many surfaces that do not emit before it is taken as lost.
    constexpr int kMaxCrossings = 64;
    const double goldenAngle = Pi * (3 - std::sqrt(5.0));
    for (const Vec3& o : origins)
        for (int i = 0; i < Effects::kSurroundProbes; ++i) {
            const double z = 1 - (2 * i + 1) / double(Effects::kSurroundProbes),
                         r = std::sqrt(std::max(0.0, 1 - z * z)), phi = goldenAngle * i;
            Ray ray{o, Vec3(r * std::cos(phi), r * std::sin(phi), z)};
            SurfaceHit hit;
            for (int crossing = 0;; ++crossing) {
                if (crossing == kMaxCrossings || !scene.surfaces->intersect(ray, NoHit, &hit))
                    return false;
                const Surface& s = surfaces[size_t(hit.surface)];
                if (s.emits()) {
                    // Its light must reach the probe (a one-sided emitter seen from behind is
                    // dark), and it must hide what lies beyond: light comes through a null or
                    // glass emitter (a sun, which NEE would sample).
                    if ((s.Le(hit.ng, -ray.d) != emitter->emission).any() || s.bsdf.transmits())
                        return false;
                    break;
                }
                ray = scene.surfaces->spawn(hit, ray.d);
            }
        }
    return true;
}

bool neePaysUnder(const Environment& env) {
    if (env.uniform() || env.black()) return false;
    return env.secondMomentRatio() >= Effects::kNeeSkySecondMomentRatio ||
           env.peak().brightestShare >= Effects::kNeeSkyBrightestShare;
}

Effects Effects::of(const Scene& scene) {
    Effects e;
    e.volumes = !scene.media.empty();
    bool scatters = false;
    for (const auto& m : scene.media) scatters |= m->scatters();
    e.surfaces = scene.surfaces != nullptr;
    if (e.surfaces)
        for (const Surface& s : scene.surfaces->surfaces()) {
            e.boundedMedia |= s.interiorMedium >= 0;
            e.emitters |= s.emits();
            // (max_records 0 asks for no records: no BRDF table is built, nor warned of)
            e.radianceCache |= scene.settings.radianceCache.enabled &&
                               scene.settings.radianceCache.maxRecords > 0 &&
                               scene.settings.maxDepth >= 1 && HshBrdfTable::supports(s.bsdf);
        }
    // Emitting surfaces of one radiance all round: every direction meets their light, and
    // render.nee "auto" draws no light sample towards them, as under a constant sky (README,
    // "Russian roulette": 11.5× as efficient in an emitting sphere of albedo-1 fog). The sky is
    // judged as before: a gap that all the probes miss must not hide a sun from next-event
    // estimation (helper 185: a hole of 0.05 sr in an emitting box went unseen). Not with the
    // radiance cache, whose records would then hold the direct light too, interpolated: its furnace
    // box with a mirror came out 0.34% dark over 8 seeds (4.2 standard errors), where next-event
    // estimation leaves the records the smoother indirect light.
    e.emissionSurrounds =
        !scene.settings.nee && !e.radianceCache && shvol::emissionSurrounds(scene);
    // render.nee: false turns off next-event estimation to every light (pure BSDF and phase
    // sampling); "auto" keeps it for area lights, unless they surround the scene.
    e.areaLights = e.emitters && scene.settings.maxDepth >= 1 &&
                   scene.settings.nee.value_or(!e.emissionSurrounds);
    e.scattering = e.volumes && scatters && scene.settings.maxDepth >= 1;
    e.multipleScattering = e.scattering && scene.settings.maxDepth > 1;
    const Environment& env = scene.environment;
    // Unless the scene says: next-event estimation pays for a shadow ray at every scattering
    // event. Under a constant sky phase sampling already draws directions in proportion to the
    // integrand apart from transmittance (and the lower hemisphere), and NEE lost in every case
    // measured, dense or thin, over the sphere or the upper hemisphere (0.06–0.73× the
    // efficiency), so it is on for skies of uneven or concentrated light only (neePaysUnder;
    // validation/sampling/README.md): an image of equal pixels is a constant sky (helper 68: NEE 7×
    // less efficient there), and one of zeros (or a scale of 0) a black one.
    const bool bounces = e.scattering || (e.surfaces && scene.settings.maxDepth >= 1);
    // (Not value_or: the argument would be evaluated, and the sky's peak found, also where
    // render.nee says.)
    e.nextEvent =
        bounces && !env.black() && (scene.settings.nee ? *scene.settings.nee : neePaysUnder(env));
    e.environmentImage = !env.isConstant();
    e.environmentBlack = env.black();
    if (e.anyNextEvent()) e.mis = scene.settings.mis;
    if (e.nextEvent) {
        e.lightSampling = scene.settings.lightSampling;
        // product_depth 0 warps by the sky alone: the wavelet strategy's distribution, which it
        // drew at 1.5–4.4× the cost (a lobe rotated and a mixture's second pdf at every event,
        // orders 4–32; helper 148). It is drawn as the wavelet strategy.
        if (e.lightSampling == LightSampling::Product && scene.settings.productDepth == 0)
            e.lightSampling = LightSampling::Wavelet;
    }
    // Russian roulette: with a survival weight where light reaches a path only where it ends
    // (killing a path there loses all it would have found); on the throughput itself where
    // next-event estimation gathers light at every vertex and bounces are dearer (README,
    // "Russian roulette": on the sunlit cloud θ = 1 was 1.28× as efficient as 0.25).
    e.rouletteThreshold = scene.settings.rrThreshold.value_or(e.anyNextEvent() ? 1.0 : 0.25);
    e.bounces = bounces;
    e.recordsSeeSmallSources =
        e.radianceCache && ((e.emitters && !e.areaLights) || (!e.nextEvent && neePaysUnder(env)));
    return e;
}

std::vector<std::string> Effects::names() const {
    std::vector<std::string> n;
    // (a black one was named "environment-constant", which misled: helper 77)
    n.push_back(environmentBlack   ? "environment-black"
                : environmentImage ? "environment-image"
                                   : "environment-constant");
    if (volumes) n.push_back(scattering ? "volume-tracking" : "volume-transmittance");
    if (scattering) n.push_back(multipleScattering ? "multiple-scattering" : "single-scattering");
    if (surfaces) n.push_back("surfaces");
    if (boundedMedia) n.push_back("bounded-media");
    if (areaLights) n.push_back("nee-area-lights");
    if (emissionSurrounds) n.push_back("emission-surrounds");
    if (radianceCache) n.push_back("radiance-cache");
    if (nextEvent) {
        switch (lightSampling) {
            case LightSampling::Environment:
                n.push_back(environmentImage ? "nee-environment-importance"
                                             : "nee-environment-uniform");
                break;
            case LightSampling::Wavelet:
                n.push_back(skyCompressed ? "nee-wavelet-compressed" : "nee-wavelet");
                break;
            case LightSampling::Product:
                n.push_back(skyCompressed ? "nee-product-compressed" : "nee-product");
                break;
        }
    }
    if (anyNextEvent()) n.push_back(std::string("mis-") + misHeuristicName(mis));
    if (bounces && rouletteThreshold < 1) n.push_back("roulette-survival-weight");
    return n;
}

const char* lightSamplingName(LightSampling s) {
    switch (s) {
        case LightSampling::Wavelet:
            return "wavelet";
        case LightSampling::Product:
            return "product";
        default:
            return "environment";
    }
}

const char* sampleStreamName(SampleStream s) {
    return s == SampleStream::Sobol ? "sobol" : "independent";
}

const char* misHeuristicName(MisHeuristic h) {
    switch (h) {
        case MisHeuristic::Power:
            return "power";
        case MisHeuristic::None:
            return "none";
        default:
            return "balance";
    }
}

}  // namespace shvol
