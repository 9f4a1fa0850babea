#pragma once
/// \file The effects a scene actually needs, decided from its content, so that a render pays only
/// for those: no media → no volume code runs; albedo 0 → no scattering is sampled; max depth 1 →
/// single scattering; constant environment → no image sampling; no surfaces → no Embree scene and
/// no surface code; no emitting surface → no area-light sampling.
#include <string>
#include <vector>

#include "shvol/render/scene.h"

namespace shvol {

struct Effects {
    bool volumes = false;             ///< at least one medium: track free flights
    bool scattering = false;          ///< some medium has albedo > 0 and max depth ≥ 1
    bool multipleScattering = false;  ///< scattering and max depth > 1
    bool nextEvent = false;           ///< NEE towards the environment (with MIS)
    bool environmentImage = false;    ///< the environment is an image (importance-sampled)
    bool environmentBlack = false;    ///< the environment gives no light (none, or all zeros)
    bool surfaces = false;            ///< the scene has surfaces (Embree closest hits)
    bool emitters = false;            ///< some surface emits
    /// some surface emits and render.nee is true, or "auto" where emission does not surround
    /// the scene: NEE to it, MIS
    bool areaLights = false;
    /// render.nee is "auto", the radiance cache off, and emitting surfaces of one radiance
    /// surround the scene (emissionSurrounds): no light sample is drawn towards them, as none is
    /// towards a constant sky (the sky itself is judged as without them).
    bool emissionSurrounds = false;
    /// Next-event estimation to any light (the sky or emitting surfaces): then MIS weights apply.
    bool anyNextEvent() const { return nextEvent || areaLights; }
    bool boundedMedia = false;  ///< some medium exists only inside a closed surface
    /// render.radiance_cache on, max_records > 0 and some surface can be cached
    bool radianceCache = false;
    /// The radiance cache's records take light straight from sources that may be small, which
    /// next-event estimation does not take for them (VolumePathIntegrator::Li leaves out what it
    /// takes): emitting surfaces without area-light sampling, or a sky of uneven or concentrated
    /// light (neePaysUnder) without NEE towards it.
    bool recordsSeeSmallSources = false;
    LightSampling lightSampling = LightSampling::Environment;  ///< strategy when nextEvent
    MisHeuristic mis = MisHeuristic::Balance;                  ///< when nextEvent
    bool skyCompressed = false;  ///< the sky hierarchy is top-K compressed (set by the integrator)
    bool bounces = false;        ///< paths scatter in media or reflect off surfaces
    /// Russian roulette's threshold θ (sampling/russian_roulette.h): render.rr_threshold, else
    /// 0.25 without next-event estimation (light reaches a path only where it ends) and 1 with it.
    double rouletteThreshold = 1;

    static Effects of(const Scene& scene);
    /// Under render.nee "auto", next-event estimation towards an image sky is drawn where its
    /// light is uneven, secondMomentRatio() m ≥ kNeeSkySecondMomentRatio, or concentrated: its
    /// brightest 1% of the directions seen (Environment::kSunSolidAngle) hold at least
    /// kNeeSkyBrightestShare of its light (Peak::brightestShare; helper 186: ten texels holding
    /// 7.1% of the light in 0.76% of the sky, m = 1.53, left pixels 3.5% low in the median at 16
    /// spp without it). Measured on the cloud of media/default.json (96×64, 16 spp, 4 seeds, 1
    /// thread; dense and ×1/20, HG 0.8 and isotropic; efficiency of NEE over phase sampling
    /// alone): make-sky's gradient sky (m = 1.36, brightest 1% holding 2.7%) 0.30–0.76×, its
    /// Preetham skies without a sun, sun high (m = 1.71–1.87, 4.1–4.7%) 0.34–0.96×, and low
    /// (m = 2.18, 6.9%: sampled) 0.53–0.83×; a soft sun holding a quarter to half of the light
    /// (m = 3.5–3.8) 0.60–2.36×, more concentrated ones (m ≥ 5.4) 0.83–7.2×, m = 48: 6.1–48×
    /// (README, "Effects").
    static constexpr double kNeeSkySecondMomentRatio = 2.5, kNeeSkyBrightestShare = 0.05;
    /// The probe directions of emissionSurrounds: kSurroundProbes points of a Fibonacci lattice
    /// on the unit sphere (equal-area bands in z, golden-angle steps in φ).
    static constexpr int kSurroundProbes = 256;
    /// Names for the statistics, e.g. {"volume-transmittance", "single-scattering", ...}.
    std::vector<std::string> names() const;
};

/// Whether emitting surfaces of one radiance surround the scene, so that phase and BSDF samples
/// meet light in every direction, as under a constant sky, where next-event estimation lost in
/// every case measured: the camera is a perspective one, every surface that emits has the same
/// emission, and every probe ray (Effects::kSurroundProbes directions from the camera's position
/// and from the centre of each bounded medium's bounds), continued through the surfaces that do
/// not emit, meets one of them on its emitting side before it escapes, one that transmits
/// nothing (not null, not glass). An estimate from finitely many rays (neighbouring directions
/// about 13° apart): a gap they all miss goes unseen, and so does a room of its own inside the
/// emitters (the probes pass its walls); either costs efficiency, never correctness, as the
/// choice of light samples does not change the expectation.
bool emissionSurrounds(const Scene& scene);

/// Whether render.nee "auto" draws light samples from the sky: not from a uniform or black one,
/// and from an image only where its light is uneven or concentrated
/// (Effects::kNeeSkySecondMomentRatio, Effects::kNeeSkyBrightestShare).
bool neePaysUnder(const Environment& env);

}  // namespace shvol
