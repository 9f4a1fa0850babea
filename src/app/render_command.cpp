#include <sys/resource.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "commands.h"
#include "mpi_world.h"
#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"
#include "shvol/core/input_file.h"
#include "shvol/core/interrupt.h"
#include "shvol/core/progress.h"
#include "shvol/io/checkpoint.h"
#include "shvol/io/exr.h"
#include "shvol/io/json_reader.h"
#include "shvol/io/provenance.h"
#include "shvol/io/scene_loader.h"
#include "shvol/phase/phase_peak.h"
#include "shvol/render/renderer.h"
#include "shvol/sampling/zonal_sh_sampler.h"

namespace shvol::app {

double peakMemoryMiB() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
}

namespace {

constexpr const char* kRenderWritesExr = "render writes OpenEXR (shvol tonemap makes a PNG)";

/// render.mis "none" warns below this many samples per pixel per unit of the sharpest lobe's peak
/// over the isotropic value (misNoneWarning).
constexpr double kMisNoneSamplesPerPeak = 4;

/// The image's stated error warns below this many degrees of freedom (Film::meanRelativeErrorDof;
/// helper 162: 7% of the renders of heavy-tailed scenes above it, 0.6% of the others below).
constexpr double kFewErrorDof = 10;
/// ... where the pixels' samples give at least this many degrees of freedom, pixels × (spp − 1),
/// so that few of them mean a heavy tail rather than few samples (renders of 4×3 pixels at 2 spp
/// have 12 in all).
constexpr double kErrorDofWarnsFrom = 1000;

/// render.nee false under an image sky warns where a pixel's samples meet its peak fewer than
/// kNeeOffPeakHitsPerPixel times, drawn evenly over the sky (neeOffPeakWarning), where the peak
/// is a sun (Environment::hasSun; without its solid-angle bound, smooth skies warned at previews'
/// samples per pixel: the circumsolar glow of make-sky's Preetham sky without a sun, below 55 spp).
constexpr double kNeeOffPeakHitsPerPixel = 4;
/// A rendered SH fit looser than this (relative L2 error), or a BRDF table whose projection or
/// peak error exceeds it, is worth a warning.
constexpr double kLooseFit = 0.1;
/// The 90th percentile of the records' irradiance relative errors above which the render warns
/// (noisyRecordsWarning).
constexpr double kNoisyRecords = 0.25;
/// A largest record error above kNoisyRecords and this many times the 90th percentile is an
/// outlier the percentile does not see (noisyRecordsWarning). The shipped scenes' largest are
/// 1.65–3.48 times theirs (README, "Record noise": the bulb at 1024 rays, cornell_fog at
/// 16,384 rays).
constexpr double kOutlierRecords = 8;
/// The second moment of light samples of a compressed sky, over the full sky's, above which the
/// render warns (compressedSkyWarning): a relative variance per sample above 1 at the cells of
/// SkyHierarchy::kMomentLevel.
constexpr double kMaxSkySecondMoment = 2;
/// A render whose share of paths ended by max_depth exceeds this (or the image mean's relative
/// standard error) is worth a warning, from this depth on (below, a low-order render is taken as
/// meant: single scattering is max_depth 1).
constexpr double kTruncatedPathsShare = 1e-3;
constexpr int kTruncationWarningDepth = 8;
/// Both are compared with the share's 95% lower bound (truncatedShareLowerBound), not the share:
/// the shipped default scene ended 0.07% of its paths at its max_depth of 128 then, and a small
/// render of it warned by chance, one path in 768 (helper 77); a rule of at least 10 paths, which
/// followed, let a render of 9 paths cut of 9, or 5 of 1536 (0.33%), say nothing (helper 94).

/// The phase function of each medium as rendered; for SH-sampled ones the resolved fit (automatic
/// order and window filled in), its error and the per-bounce weight moment m₂.
nlohmann::json phaseJson(const PhaseFunction& p) {
    nlohmann::json j;
    const auto* sh = std::get_if<SHSampledPhase>(&p.variant());
    j["type"] = sh ? sh->base().name() : p.name();
    j["sampling"] = sh ? "sh" : "analytic";
    if (!sh) return j;
    j["order"] = sh->fit().p.size();
    j["window"] = shWindowName(sh->fit().window);
    j["evaluate"] = sh->evaluate() == SHSampledPhase::Evaluate::Exact ? "exact" : "sh";
    j["sh_depth"] = sh->sampler().depth();
    j["relative_l2_error"] = sh->fit().relativeL2Error;
    j["rendered_relative_l2_error"] = sh->renderedRelativeL2Error();
    j["weight_second_moment"] = sh->weightSecondMoment();
    j["clamped_bins_fraction"] = sh->sampler().clampedFraction();
    return j;
}

/// Whether an SH-sampled phase function's weight alone is warned of: m₂ above
/// SHSampledPhase::kUnreliableSecondMoment (exact evaluation: the reconstruction's m₂ is 1).
bool unreliablePerBounce(const SHSampledPhase& sh) {
    return sh.weightSecondMoment() > SHSampledPhase::kUnreliableSecondMoment;
}

/// The compounded second moment E[m₂^k] of the SH-sampled phase weights along the camera paths
/// above which a render warns (phase_weight_moments.h): e, what the per-bounce warning's 1.01
/// reaches after 100 bounces.
constexpr double kCompoundedPhaseMoment = 2.718281828459045;

/// The warning of SH-sampled phase weights that compound along the render's paths although no
/// medium's per-bounce m₂ is warned of (phaseWarnings); empty if none.
std::string compoundedPhaseWarning(const Scene& scene, const PhaseWeightMoments& pw) {
    std::string media;
    double largest = 1;
    for (size_t i = 0; i < scene.media.size(); ++i) {
        const auto* sh = std::get_if<SHSampledPhase>(&scene.media[i]->phase().variant());
        if (!sh || !(sh->weightSecondMoment() > 1)) continue;  // (a weight of 1 does not compound)
        if (unreliablePerBounce(*sh)) return "";               // (said per bounce already)
        media += (media.empty() ? "media[" : ", media[") + std::to_string(i) + "].phase";
        largest = std::max(largest, sh->weightSecondMoment());
    }
    const double m = pw.meanLowerBound();
    if (media.empty() || !(m > kCompoundedPhaseMoment)) return "";
    char msg[700];
    std::snprintf(msg, sizeof msg,
                  ": the SH-sampled weights p/pdf (\"evaluate\": \"exact\") compound along the "
                  "paths to a second moment of at least %.3g on average (%.3g%% of the paths "
                  "beyond e), though a bounce's is at most %.6g: so many scattering events make "
                  "multiply-scattered light noisy and underestimated in practice; use "
                  "\"evaluate\": \"sh\"",
                  m, 100 * pw.shareFrom(int(std::round(1 / PhaseWeightMoments::kBin))), largest);
    return media + msg;
}

/// Warnings about SH-sampled phase functions that make a render unreliable (issue 10 §1).
std::vector<std::string> phaseWarnings(const Scene& scene) {
    std::vector<std::string> w;
    for (size_t i = 0; i < scene.media.size(); ++i) {
        const auto* sh = std::get_if<SHSampledPhase>(&scene.media[i]->phase().variant());
        if (!sh) continue;
        char msg[600];
        const int order = int(sh->fit().p.size());
        // (at the highest order a higher one is no advice; helpers 146, 151)
        const bool highest = order >= ZonalFitRequest::kMaxAutoOrder;
        if (const std::string blind = blindSHFitText(*sh); !blind.empty())
            w.push_back("media[" + std::to_string(i) + "].phase: " + blind +
                        "; use \"sampling\": \"analytic\"");
        if (unreliablePerBounce(*sh)) {
            const double m2 = sh->weightSecondMoment();
            std::snprintf(msg, sizeof msg,
                          "media[%zu].phase: the SH-sampled weight p/pdf has second moment %.4g "
                          "per bounce (%.3g after 100 bounces): multiply-scattered light will be "
                          "noisy and underestimated in practice; use \"evaluate\": \"sh\" or %s",
                          i, m2, std::pow(m2, 100),
                          highest ? "\"sampling\": \"analytic\" (this is the highest order)"
                                  : "a higher order");
            w.push_back(msg);
        }
        if (sh->evaluate() == SHSampledPhase::Evaluate::Reconstruction &&
            sh->renderedRelativeL2Error() > kLooseFit) {
            // A loose fit needs a higher order, at the highest one the function itself. A close
            // fit drawn loosely needs finer z-bins, and where it dips below 0 its bins are
            // clamped, which finer bins do not mend (HG 0.97 at order 115 without a window, 46%
            // clamped: 0.145 at depth 16, 0.144 at 22; review). ("evaluate": "exact" is not
            // offered: where a fit is this loose its weight's second moment explodes, README.)
            const int depth = sh->sampler().depth();
            const double clamped = sh->sampler().clampedFraction();
            char dips[160] = "";
            if (clamped > 0)
                std::snprintf(dips, sizeof dips,
                              "; or mend its dips below 0, clamped in %.3g%% of the bins: "
                              "\"window\": \"hann\"%s",
                              100 * clamped, highest ? "" : " or a higher order");
            const std::string advice =
                sh->fit().relativeL2Error > kLooseFit
                    ? (highest ? "that is the highest order: use \"sampling\": \"analytic\""
                               : "raise \"order\" or use \"order\": \"auto\"")
                : depth < SHSampledPhase::kMaxDepth
                    ? std::string(
                          "raise \"sh_depth\": the sampler draws the fit averaged over "
                          "its z-bins") +
                          dips
                    : std::string("use \"sampling\": \"analytic\"") + dips;
            std::snprintf(msg, sizeof msg,
                          "media[%zu].phase: the phase function rendered is its order-%d SH fit "
                          "drawn over 2^%d z-bins, with relative L2 error %.3g (the fit's own "
                          "%.3g); %s",
                          i, order, depth, sh->renderedRelativeL2Error(), sh->fit().relativeL2Error,
                          advice.c_str());
            w.push_back(msg);
        }
    }
    return w;
}

/// Warnings about surfaces too small for the scene's ray offset ε (SurfaceScene: 2⁻¹⁶ of the
/// surfaces' extent from the centre of their box, set by float intersection): rays leaving such a
/// surface skip more than 1% of it, and hits near it are unreliable (a glass sphere of radius 1
/// beside a floor 10⁵ wide: ε = 1.5 ended paths inside it). A surface's size is its largest
/// extent, or for a closed mesh that rays pass through (glass, a medium's boundary) its thickness
/// 2V/A where that is less. Two surfaces closer than 10 ε are warned of too.
std::vector<std::string> surfaceWarnings(const Scene& scene) {
    std::vector<std::string> w;
    if (!scene.surfaces) return w;
    const double eps = scene.surfaces->epsilon();
    // ε is 2⁻¹⁶ of the surfaces' extent, or, far from the origin, 32 steps of a double there
    // (SurfaceScene): the remedy differs (review).
    const Vec3 lo = scene.surfaces->lower(), hi = scene.surfaces->upper();
    const bool far = eps > std::ldexp(0.5 * (hi - lo).maxCoeff(), -16) * (1 + 1e-9);
    const std::string offsetOrigin =
        far ? "32 steps of a double at the surfaces' distance from the origin"
            : "2^-16 of the surfaces' extent";
    const std::string remedy =
        far ? "bring the scene nearer the origin" : "bring the scene's surfaces closer together";
    // Each surface's box once (a mesh's walks its vertices), for its size and the gaps below.
    const std::vector<Surface>& all = scene.surfaces->surfaces();
    std::vector<Bounds3> boxes;
    for (const Surface& s : all) boxes.push_back(s.bounds());
    for (size_t k = 0; k < all.size(); ++k) {
        const Surface& s = all[k];
        // (as the scene's other unused keys are said; helper 143)
        if (s.twoSidedEmission && !s.emits())
            w.push_back(s.name + ": emission_two_sided is not used: the surface does not emit");
        // Glass that is not a solid's surface (a medium's boundary must be one: refused): a ray
        // that enters it need not meet a face to leave by, and its faces are not turned to face
        // outwards (helper 66: open, flipped and non-manifold glass rendered without a word).
        if (s.kind == Surface::Kind::Mesh && s.bsdf.type == BsdfType::Dielectric &&
            !s.solidity().defect.empty())
            w.push_back(s.name +
                        (s.solidity().partsMeet
                             ? ": dielectric, and its parts cross or touch (" +
                                   s.solidity().defect +
                                   "): where they meet, a ray in one part meets the other's "
                                   "faces as if from outside the glass and refracts there; each "
                                   "part that meets another was turned to face outwards on its "
                                   "own"
                             : ": dielectric, but not the closed surface of a solid (" +
                                   s.solidity().defect +
                                   "): light that enters it may leave it only where a face "
                                   "happens to lie, and its faces were not turned to face "
                                   "outwards (an open sheet meant so, a water surface, is "
                                   "rendered as wound: its normals point out of the glass)"));
        // A rectangle or disk is a sheet, never a solid's surface: the same case (helper 94: a
        // glass disk rendered a white furnace at 0.48 from its front, 1 from behind, silently).
        if ((s.kind == Surface::Kind::Rectangle || s.kind == Surface::Kind::Disk) &&
            s.bsdf.type == BsdfType::Dielectric)
            w.push_back(
                s.name + ": dielectric, but a " +
                (s.kind == Surface::Kind::Disk ? "disk" : "rectangle") +
                " is an open sheet, not the closed surface of a solid: light that enters it "
                "through its front leaves only where another face happens to lie (a white "
                "furnace seen through a glass disk renders 0.48 to 0.55 for 1); it is rendered "
                "as the front of glass, its normal pointing out of it; for a pane, use a closed "
                "mesh");
        double size = (boxes[k].hi - boxes[k].lo).maxCoeff();
        // A closed mesh that rays pass through is judged by its thickness, 2V/A (a slab's: a pane
        // 2 wide and 0.0002 thick, under an offset beyond 0.0002, kept every refracted ray inside
        // it, and its 1/η² radiance scale: the wall behind it 0.44 where 0.95 is right).
        bool thick = false;
        if (s.kind == Surface::Kind::Mesh && (s.bsdf.transmits() || s.interiorMedium >= 0) &&
            s.solidity().defect.empty()) {
            const double t = 2 * std::abs(s.solidity().signedVolume) / surfaceArea(s.mesh);
            if (t < size) size = t, thick = true;
        }
        if (!(eps > 0.01 * size)) continue;
        char msg[400];
        std::snprintf(msg, sizeof msg,
                      ": %.3g %s, and the ray offset is %.3g (%s): rays leaving it skip more than "
                      "1%% of it, and light near it is unreliable; %s",
                      size, thick ? "thick (2V/A)" : "across", eps, offsetOrigin.c_str(),
                      remedy.c_str());
        w.push_back(s.name + msg);
    }
    // Two surfaces whose boxes are less than 10 ε apart (and not touching, where nothing can be
    // told): rays leaving one skip more than a tenth of the gap, all of it below ε (helper 80: a
    // floor 10⁵ wide under an emitting ceiling 1 above it, ε = 1.53, rendered black without a
    // word). Boxes: the surfaces themselves may be farther apart. Two spheres by their surfaces'
    // own gap, which nested ones have inside overlapping boxes (a glass shell 10⁻⁵ thick in a
    // scene of ε 1.5·10⁻⁵ was jumped without a word; helper 101); crossing ones have none. One
    // warning, naming the closest pair (a tiled scene would give one per pair).
    size_t pairs = 0, closestA = 0, closestB = 0;
    double closest = INFINITY;
    const auto sphereGap = [](const Surface& a, const Surface& b) {
        const double d = (a.center - b.center).norm();
        return std::max({0.0, d - a.radius - b.radius, std::abs(a.radius - b.radius) - d});
    };
    // Sweep and prune: a pair less than 10 ε apart (boxes, or spheres, whose surfaces lie inside
    // their boxes) is less than 10 ε apart along every axis, so along one axis only boxes that
    // reach within 10 ε of one another's span are compared: along the axis where the fewest do
    // (every pair was compared until 7 Dec: 64,000 spheres took 29 s to set up an 8×8 image, and
    // spheres in a plane across the longest axis as long; helper 127). The closest pair, ties to
    // the lowest indices, is the one every pair's loop named.
    const double reach = 10 * eps;
    // Compared where their spans come within twice that: a sphere's gap, from its centre and
    // radius, rounds otherwise than its box's bounds, and a pair 10 ε apart to the last digits was
    // warned of along one axis and not along another (helper 129); ε is at least 32 steps of a
    // double at the surfaces' coordinates, so 10 ε more is slack of hundreds of steps.
    const double prune = 2 * reach;
    int axis = 0;
    double fewest = INFINITY;
    std::vector<size_t> order(all.size());
    for (int a = 0; a < 3; ++a) {
        std::vector<double> starts(all.size());
        for (size_t k = 0; k < all.size(); ++k) starts[k] = boxes[k].lo[a];
        std::sort(starts.begin(), starts.end());
        double candidates = 0;  // Σ over boxes of the boxes starting in [lo, hi + prune)
        for (size_t k = 0; k < all.size(); ++k)
            candidates +=
                double(std::lower_bound(starts.begin(), starts.end(), boxes[k].hi[a] + prune) -
                       std::lower_bound(starts.begin(), starts.end(), boxes[k].lo[a]));
        if (candidates < fewest) fewest = candidates, axis = a;
    }
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](size_t p, size_t q) {
        return std::tie(boxes[p].lo[axis], p) < std::tie(boxes[q].lo[axis], q);
    });
    for (size_t p = 0; p < order.size(); ++p)
        for (size_t q = p + 1; q < order.size(); ++q) {
            const size_t i = std::min(order[p], order[q]), j = std::max(order[p], order[q]);
            if (!(boxes[order[q]].lo[axis] - boxes[order[p]].hi[axis] < prune)) break;
            const Bounds3 &a = boxes[i], &b = boxes[j];
            const double gap =
                all[i].kind == Surface::Kind::Sphere && all[j].kind == Surface::Kind::Sphere
                    ? sphereGap(all[i], all[j])
                    : (a.lo - b.hi).cwiseMax(b.lo - a.hi).cwiseMax(Vec3::Zero()).norm();
            if (!(gap > 0 && gap < reach)) continue;
            ++pairs;
            if (std::tie(gap, i, j) < std::tie(closest, closestA, closestB))
                closest = gap, closestA = i, closestB = j;
        }
    if (pairs > 0) {
        char msg[500];
        std::snprintf(
            msg, sizeof msg,
            " and %s are %.3g apart%s, and the ray offset is %.3g (%s): rays leaving one skip "
            "more than a tenth of the gap%s, and light between them is unreliable; %s",
            all[closestB].name.c_str(), closest,
            pairs > 1 ? (" (the closest of " + std::to_string(pairs) + " such pairs)").c_str() : "",
            eps, offsetOrigin.c_str(),
            closest <= eps ? " (all of it: they see past each other)" : "",
            far ? remedy.c_str()
                : "make the surfaces' extent smaller, which sets the offset, or the gap wider");
        w.push_back(all[closestA].name + msg);
    }
    return w;
}

/// Why next-event estimation towards the environment is on or off (Effects::of), in words: the
/// stats' next_event_estimation.why, and the unused light sampler's warning.
std::string neeReason(const Scene& scene, const Effects& effects) {
    const Environment& env = scene.environment;
    if (!effects.bounces) return "no path scatters or reflects";
    if (env.black()) return "the environment is black";
    if (scene.settings.nee)
        return *scene.settings.nee ? "render.nee is true" : "render.nee is false";
    if (env.isConstant() || env.uniform())
        return std::string("render.nee \"auto\" leaves it off under a ") +
               (env.isConstant() ? "constant sky" : "sky image of equal pixels") +
               ", where phase sampling does better";
    // (neePaysUnder's two measures against their bounds, Effects::kNeeSkySecondMomentRatio and
    // kNeeSkyBrightestShare; the second only where the first does not decide.)
    const double m = env.secondMomentRatio();
    char text[240];
    if (m >= Effects::kNeeSkySecondMomentRatio) {
        std::snprintf(text, sizeof text,
                      "render.nee \"auto\" turns it on under a sky image whose light is uneven "
                      "(m = 4π ∫Y² dω / (∫Y dω)² = %.3g, at least %g)",
                      m, Effects::kNeeSkySecondMomentRatio);
        return text;
    }
    const double brightest = env.peak().brightestShare;
    if (effects.nextEvent)
        std::snprintf(text, sizeof text,
                      "render.nee \"auto\" turns it on under a sky image whose light is "
                      "concentrated (its brightest 1%% hold %.2g%% of it, %g%% or more)",
                      100 * brightest, 100 * Effects::kNeeSkyBrightestShare);
    else
        std::snprintf(text, sizeof text,
                      "render.nee \"auto\" leaves it off under a sky image whose light is even "
                      "(m = 4π ∫Y² dω / (∫Y dω)² = %.3g, under %g; its brightest 1%% hold %.2g%% "
                      "of it, under %g%%), where phase sampling does better",
                      m, Effects::kNeeSkySecondMomentRatio, 100 * brightest,
                      100 * Effects::kNeeSkyBrightestShare);
    return text;
}

/// Why no next-event estimation is done at all, towards the environment or area lights (render.nee
/// false names itself: neeReason, about the environment, said "the environment is black" of a
/// Cornell box whose lamp render.nee false left unsampled; and of a lamp all round, which "auto"
/// leaves unsampled, Effects::emissionSurrounds).
std::string noNextEventReason(const Scene& scene, const Effects& effects) {
    if (scene.settings.nee == false) return "render.nee is false";
    if (effects.emissionSurrounds)
        return "render.nee \"auto\" leaves it off where emitting surfaces of one radiance "
               "surround the scene, where phase and BSDF sampling do better";
    return neeReason(scene, effects);
}

/// The end of a warning that next-event estimation is off: why, and, where render.nee true would
/// turn on what the warning is about (`settable`), how, with the closing parenthesis.
std::string neeOffWhy(const std::string& reason, bool settable) {
    return reason + (settable ? "; set render.nee to true to use it)" : ")");
}

/// A light sampler other than the default asked for (render.light_sampling) where next-event
/// estimation, which draws its samples, is off: it would go unused without a word (the stats'
/// effects alone showed it). "" when it is used, or not asked for.
std::string unusedLightSamplingWarning(const Scene& scene, const Effects& effects) {
    const RenderSettings& s = scene.settings;
    if (s.lightSampling == LightSampling::Environment || effects.nextEvent) return "";
    return std::string("render.light_sampling: \"") + lightSamplingName(s.lightSampling) +
           "\" is not used: next-event estimation, which draws its samples, is off (" +
           neeOffWhy(neeReason(scene, effects),
                     !s.nee && effects.bounces && !scene.environment.black());
}

/// A weighting other than the default asked for (render.mis) where no light sample is drawn at
/// all, towards the sky or an emitting surface: "none" rendered as "balance" would, without a
/// word (helper 111). "" when it is used, or not asked for.
std::string unusedMisWarning(const Scene& scene, const Effects& effects) {
    const RenderSettings& s = scene.settings;
    if (s.mis == MisHeuristic::Balance || effects.anyNextEvent()) return "";
    // (Not neeReason, which is about the sky alone: a Cornell box under render.nee false was
    // said to lack light samples because its environment is black. A black sky with no emitter
    // comes first: render.nee true would not draw any either; helper 115.)
    const bool black = scene.environment.black();
    const std::string why = !effects.bounces ? neeReason(scene, effects)
                            : black && !effects.emitters
                                ? "the environment is black and no surface emits"
                                : noNextEventReason(scene, effects);
    return std::string("render.mis: \"") + misHeuristicName(s.mis) +
           "\" is not used: no light sample is drawn, as next-event estimation is off (" +
           neeOffWhy(why, !s.nee && effects.bounces && (!black || effects.emitters));
}

/// render.nee false under an image sky whose peak (Environment::peak: the brightest texels that
/// hold half of ∫ Y² dω, a sun) paths meet only by phase or BSDF sampling: a direction drawn
/// evenly over the sky meets it with probability Ω_peak/Ω_seen, so a pixel's samples meet it
/// about spp·Ω_peak/Ω_seen times. Below kNeeOffPeakHitsPerPixel most pixels miss the light it
/// holds and come out low, a few far too bright, and their standard errors do not show it
/// (helper 160: g 0.99 under media/sunsky.exr, 16–256 spp, every render about 10% low where its
/// image_mean_relative_error said 0.15%: z down to −268). No statistic of the samples can see
/// light no sample met, so the sky itself is judged. "" where it does not apply.
std::string neeOffPeakWarning(const Scene& scene, const Effects& effects) {
    const Environment& sky = scene.environment;
    if (scene.settings.nee != false || !effects.bounces || sky.isConstant() || sky.uniform())
        return "";
    const Environment::Peak peak = sky.peak();
    const double seen = sky.lowerHemisphereBlack() ? TwoPi : FourPi;
    const double hits = scene.settings.spp * peak.solidAngle / seen;
    if (!(hits < kNeeOffPeakHitsPerPixel && sky.hasSun())) return "";
    char msg[800];
    std::snprintf(msg, sizeof msg,
                  "render.nee: false under an image sky whose brightest %.3g sr (%.2g%% of the "
                  "sky seen) hold %.0f%% of its light: paths meet them only by phase or BSDF "
                  "sampling, about %.2g times in a pixel's %d samples, so most pixels come out "
                  "low and a few far too bright, with standard errors that do not show it; leave "
                  "render.nee \"auto\" (on under an image sky with a sun)",
                  peak.solidAngle, 100 * peak.solidAngle / seen, 100 * peak.powerShare, hits,
                  scene.settings.spp);
    // (The samples that would meet it often enough, as an integer: "1.08e+03" read as fewer than
    // the 1097 it was; helper 163.)
    const double enough = std::ceil(kNeeOffPeakHitsPerPixel * seen / peak.solidAngle);
    return msg +
           (enough <= double(kMaxSpp)
                ? ", or render " + std::to_string((long long)enough) + " samples per pixel or more"
                : std::string(": the samples per pixel that would meet it often enough are "
                              "beyond render.spp's 2^24"));
}

/// render.mis "none" where light samples alone cannot converge at the render's samples per
/// pixel: a light sample meets a phase lobe (or a BSDF's, Bsdf's peakOverIsotropic) that peaks
/// at P = 4π·p_max times the isotropic value about once in P draws, and with fewer samples per
/// pixel than a few times P most pixels come out low, a few far too high (white furnace, τ = 4,
/// 15 phase functions: the median pixel over the truth depends on spp/P alone, 0.3 at 0.02, 0.57
/// at 0.08, 0.82 at 0.35, 0.95 at 1.3, 0.976 or more from 3.4; balance MIS 1.000 at every spp;
/// helper 91). "" where it does not apply or spp ≥ kMisNoneSamplesPerPeak·P for every scattering
/// medium and surface.
std::string misNoneWarning(const Scene& scene, const Effects& effects) {
    // (Not where next-event estimation samples area lights alone: a small light is reached by
    // light samples better than by the lobe, and the Cornell box's Phong wall, warned of below
    // 121 spp, came out as well with "none" as with "balance": median pixel 0.897 against 0.896
    // at 4 spp; helper 109. A large emitting enclosure is the case left unwarned: fog of HG 0.9
    // in one, 1.73 ± 0.26 for 2 at 64 spp; helper 108.)
    if (!effects.nextEvent || effects.mis != MisHeuristic::None) return "";
    double peak = 0;
    std::string which;
    for (size_t i = 0; i < scene.media.size(); ++i)
        if (scene.media[i]->scatters())
            if (const double p = peakOverIsotropic(scene.media[i]->phase()); p > peak)
                peak = p, which = "media[" + std::to_string(i) + "]'s phase function";
    // (A glossy BSDF's lobe is met by light samples alone as rarely.)
    if (scene.surfaces)
        for (const Surface& s : scene.surfaces->surfaces())
            if (const double p = peakOverIsotropic(s.bsdf); p > peak)
                peak = p, which = s.name + "'s BSDF";
    if (!(kMisNoneSamplesPerPeak * peak > scene.settings.spp)) return "";
    char msg[800];
    std::snprintf(msg, sizeof msg,
                  "render.mis: \"none\" with %d samples per pixel, and %s peaks at %.3g times "
                  "the isotropic value: light samples alone rarely meet its lobe, so most pixels "
                  "come out low and a few far too high (a white furnace's median pixel is 5%% "
                  "low at 1.3 times as many samples as the peak, 43%% at 0.08 times, within 2.5%% "
                  "from 3.4 times); use \"balance\" or \"power\", or %.3g samples per pixel or "
                  "more",
                  scene.settings.spp, which.c_str(), peak, kMisNoneSamplesPerPeak * peak);
    return msg;
}

/// environment.wavelet_coefficients where no sky hierarchy is built (light sampling "environment",
/// or next-event estimation off, as under a constant sky): the key changes nothing.
std::string unusedWaveletWarning(const Scene& scene, const Effects& effects) {
    const RenderSettings& s = scene.settings;
    if (s.waveletCoefficients == 0 ||
        (effects.nextEvent && effects.lightSampling != LightSampling::Environment))
        return "";
    return "environment.wavelet_coefficients: " + std::to_string(s.waveletCoefficients) +
           " is not used: the wavelet sky is built only for light_sampling \"wavelet\" or "
           "\"product\" with next-event estimation on";
}

/// Keys the scene gives that change nothing in this render: a sweep over one rendered the same
/// image under two names, without a word (helper 122). The product lobe's without product
/// sampling or without a scattering medium (its light sampler's own warning covers product
/// sampling with next-event estimation off), the radiance cache's with the cache off, the
/// transmittance estimator where no transmittance is estimated, a VDB medium's majorant cell
/// without a majorant grid. Read from the scene as given (doc), so that a value given as its
/// default is said too. `keys` (optional) gets the JSON pointer of every such key.
std::vector<std::string> unusedKeyWarnings(const Json& doc, const Scene& scene,
                                           const Effects& effects,
                                           std::vector<std::string>* keys = nullptr) {
    std::vector<std::string> w;
    // (a key's pointer, and the warning when there is one: the cache's keys share theirs)
    const auto unused = [&](const std::string& pointer, std::string warning) {
        if (keys) keys->push_back(pointer);
        if (!warning.empty()) w.push_back(std::move(warning));
    };
    const Json render = doc.value("render", Json::object());
    const RenderSettings& s = scene.settings;
    // (The product's lobe is a phase function's: surfaces draw no product sample; helper 124.)
    const bool product = s.lightSampling == LightSampling::Product;
    for (const std::string key : {"product_order", "product_depth"}) {
        std::string why;  // why the key shapes nothing ("" where it is used)
        if (!product)
            why = std::string("it shapes light_sampling \"product\", and this render's is \"") +
                  lightSamplingName(s.lightSampling) + "\"";
        else if (!effects.scattering)
            why = "it shapes the phase lobes of light_sampling \"product\", and no medium scatters";
        else if (key == "product_order" && s.productDepth == 0)  // (Effects::of)
            why = "product_depth 0 warps by the sky alone, which is light_sampling \"wavelet\"";
        if (render.contains(key) && !why.empty())
            unused("/render/" + key,
                   "render." + key + ": " + render[key].dump() + " is not used: " + why);
    }
    const Json cache = render.value("radiance_cache", Json::object());
    // A cached vertex's direct light is light_samples next-event samples: with next-event
    // estimation off none is drawn (1 and 8 rendered bit-identical images; helper 132).
    if (cache.is_object() && cache.contains("light_samples") && effects.radianceCache &&
        !effects.anyNextEvent())
        unused("/render/radiance_cache/light_samples",
               "render.radiance_cache.light_samples: " + cache["light_samples"].dump() +
                   " is not used: next-event estimation is off (" +
                   noNextEventReason(scene, effects) +
                   "), and the BSDF sample carries a cached vertex's direct light");
    // (max_records 0 makes no records: the cache is off too; helper 137)
    const bool noRecords = s.radianceCache.enabled && s.radianceCache.maxRecords == 0;
    if (!s.radianceCache.enabled || noRecords) {
        std::string names;
        int n = 0;
        for (auto it = cache.begin(); it != cache.end(); ++it)
            if (it.key() != "enabled" && (!noRecords || it.key() != "max_records")) {
                names += (n++ ? ", " : "") + it.key();
                unused("/render/radiance_cache/" + it.key(), "");
            }
        if (n > 0)
            w.push_back("render.radiance_cache: " + names + (n == 1 ? " is" : " are") +
                        " not used: the cache is off (" +
                        (noRecords ? "max_records is 0: it makes no records"
                                   : "set render.radiance_cache.enabled to true to use it") +
                        ")");
    }
    // Without next-event estimation the only transmittance estimated is that of a camera ray
    // through media that do not scatter, in a scene without surfaces (the radiance cache's
    // light step and records' direct light need next-event estimation too; helper 124).
    if (render.contains("transmittance") &&
        (!effects.volumes || (!effects.anyNextEvent() && (effects.scattering || effects.surfaces))))
        unused("/render/transmittance",
               "render.transmittance: " + render["transmittance"].dump() +
                   " is not used: no transmittance is estimated, " +
                   (!effects.volumes
                        ? std::string("as the scene has no medium")
                        : "as next-event estimation is off (" + noNextEventReason(scene, effects) +
                              ") and free flights carry the paths"));
    const Json media = doc.value("media", Json::array());
    for (size_t i = 0; media.is_array() && i < media.size(); ++i)
        if (media[i].is_object() && media[i].contains("majorant_cell") &&
            media[i].value("majorant_grid", true) == false)
            unused("/media/" + std::to_string(i) + "/majorant_cell",
                   "media[" + std::to_string(i) +
                       "].majorant_cell: " + media[i]["majorant_cell"].dump() +
                       " is not used: majorant_grid is false (one global majorant)");
    return w;
}

/// A radiance cache whose records fit their n² HSH coefficients each to fewer than 4n² rays: the
/// records' noise is frozen into every pixel they serve (a white furnace at order 20 with the
/// default 1024 rays: RMSE 0.0072 against 0.00068 at order 8, 0.0018 with 4096 rays; the Cornell
/// box at 1 and 4 rays: regions off by up to 250%; helper 63's audit).
std::string fewRaysPerRecordWarning(const Scene& scene, const Effects& effects) {
    const RadianceCacheSettings& rc = scene.settings.radianceCache;
    const int coefficients = rc.hshOrder * rc.hshOrder;
    if (!effects.radianceCache || rc.raysPerRecord >= 4 * coefficients) return "";
    return "render.radiance_cache: " + std::to_string(rc.raysPerRecord) +
           " rays_per_record for the " + std::to_string(coefficients) +
           " HSH coefficients of order " + std::to_string(rc.hshOrder) +
           ": each record is a noisy fit, and its noise is in every pixel it serves; give at "
           "least " +
           std::to_string(4 * coefficients) + " rays (4 per coefficient)";
}

/// Records whose irradiance estimates are noisy (RadianceCacheStats::recordErrorP90 above
/// kNoisyRecords): their noise is frozen into every pixel they serve, as blotches that more
/// samples per pixel do not remove. The figure does not tell harm near the threshold (README,
/// "Record noise"): `cornell_fog.json` at the defaults, 0.174, has records' noise of 3.4% of its
/// mean pixel; a wall lit by a tiny bulb, 0.18–0.22 at 1024 rays, regions 8–49% off by the seed
/// (helper 105); neither is warned of, the bulb at 256 rays (0.44) is. Advises the rays that would
/// bring the 90th percentile to 0.1 if the error fell as 1/√N, as a power of two. "" when the
/// records are not noisy.
std::string noisyRecordsWarning(const Scene& scene, const RadianceCacheStats& rc) {
    if (!rc.used) return "";
    const bool many = rc.recordErrorP90 > kNoisyRecords;
    // Or a few records far noisier than the rest: a rare bright path (light through glass, off a
    // mirror) that one of their rays met. milk_glass at 32×24 had one at 0.84 beside a 90th
    // percentile of 0.040, and pixels it served 2–5 times too bright, without a word (helper 155).
    const bool outlier = !many && rc.recordErrorMax > kNoisyRecords &&
                         rc.recordErrorMax > kOutlierRecords * rc.recordErrorP90;
    if (!many && !outlier) return "";
    const int rays = scene.settings.radianceCache.raysPerRecord;
    const double needed = rays * sqr((many ? rc.recordErrorP90 : rc.recordErrorMax) / 0.1);
    long long advised = 1;
    while (advised < needed && advised < (1LL << 40)) advised *= 2;
    char msg[560];
    if (outlier) {
        std::snprintf(
            msg, sizeof msg,
            "render.radiance_cache: the noisiest record's irradiance estimate is far noisier than "
            "the others' (relative standard error %.3g, where the 90th percentile is %.3g and "
            "the median %.3g), most likely a rare bright path (light through glass, off a "
            "mirror) that one of its %d rays met; it shows as a blotch in the pixels that record "
            "serves, which more samples per pixel do not remove; render without the cache, or give "
            "more rays_per_record (about %lld if the error fell as 1/√N, which so rare a path does "
            "not promise)",
            rc.recordErrorMax, rc.recordErrorP90, rc.recordErrorMedian, rays, advised);
        return msg;
    }
    std::snprintf(
        msg, sizeof msg,
        "render.radiance_cache: the records' irradiance estimates are noisy (relative "
        "standard error, as if their %d rays were independent: median %.3g, 90th "
        "percentile %.3g, largest %.3g), most likely light from a small bright patch that "
        "few rays meet; the noise shows as blotches in every pixel a record serves, and "
        "more samples per pixel do not remove it; give about %lld rays_per_record",
        rays, rc.recordErrorMedian, rc.recordErrorP90, rc.recordErrorMax, advised);
    return msg;
}

/// A sky hierarchy compressed (environment.wavelet_coefficients) until light samples of it have
/// more than kMaxSkySecondMoment times the second moment of the full sky's
/// (SkyHierarchy::lightSecondMoment): the light it leaves out, a sun, is reached by phase and BSDF
/// samples alone. Unbiased with MIS, but noisy: a sun compressed away at 8 coefficients gave 30
/// times the standard error of the uncompressed sky at the same cost (helper 108), and at 64
/// (relative L2 error 0.049, second moment 35) 2.4–6 times the RMSE, which the L2 error, this
/// warning's first measure, did not see (helper 109). "" otherwise.
std::string compressedSkyWarning(const RenderStats& st) {
    const LightSamplingStats& ls = st.lightSampling;
    if (!(ls.waveletSecondMoment > kMaxSkySecondMoment)) return "";
    char msg[480];
    std::snprintf(msg, sizeof msg,
                  "environment.wavelet_coefficients: the %zu kept of %zu give light samples of the "
                  "sky %.3g times the second moment of the full sky's (relative L2 error %.3g): "
                  "light the compression leaves out (a sun) is reached by phase and BSDF samples "
                  "alone, which makes the image noisy; keep more coefficients (0 keeps all)",
                  ls.waveletKept, ls.waveletDetails, ls.waveletSecondMoment, ls.waveletL2Error);
    return msg;
}

/// Warnings only the render can give: a radiance cache whose BRDF tables hold the BRDF poorly (a
/// sharp lobe at a low HSH order: the cached light is then too dark or blurred), naming each
/// such surface.
std::vector<std::string> renderWarnings(const Scene& scene, const RenderStats& st) {
    std::vector<std::string> w;
    // Where the records take light straight from sources that may be small
    // (Effects::recordsSeeSmallSources), a highlight is off by up to the table's peak error (Phong
    // 30 at order 8, projection error 0.082, gave no warning while its highlight under a small
    // lamp was 7.9% dark and its dim edges 88%; helper 105). Otherwise the projection error alone
    // decides: the records then hold a uniform sky and light that has bounced (small sources seen
    // through a mirror or glass too, which this does not weigh).
    const bool smallSources = Effects::of(scene).recordsSeeSmallSources;
    for (const BrdfTableErrors& e : st.radianceCache.tableErrors) {
        const bool peaked = smallSources && e.peak > kLooseFit;
        if (!(e.projection > kLooseFit) && !peaked) continue;
        char msg[400], sources[160] = "";
        if (peaked)
            std::snprintf(sources, sizeof sources,
                          " (light straight from small sources, which the records carry without "
                          "next-event estimation, by up to %.3g%% of the lobe's peak)",
                          100 * e.peak);
        std::snprintf(
            msg, sizeof msg,
            ": its BRDF table holds the BRDF with relative projection error %.3g and peak "
            "error %.3g at HSH order %d: cached light on it is biased%s; raise "
            "render.radiance_cache.hsh_order, or leave such sharp lobes uncached",
            e.projection, e.peak, scene.settings.radianceCache.hshOrder, sources);
        w.push_back(e.surface + msg);
    }
    for (const auto& [surface, error] : st.radianceCache.uncached) {
        char msg[240];
        std::snprintf(msg, sizeof msg,
                      ": its BRDF lobe is too narrow for the radiance cache's BRDF table (the "
                      "table's albedo is off by %.3g%%): the surface is path traced, not cached",
                      100 * error);
        w.push_back(surface + msg);
    }
    // (A cache is used only with max_records > 0: 0 asks for no records, and this advised raising
    // it; helper 105.)
    if (const int cap = scene.settings.radianceCache.maxRecords;
        st.radianceCache.used && st.radianceCache.records >= size_t(cap))
        w.push_back("render.radiance_cache: the fill stopped at max_records (" +
                    std::to_string(cap) +
                    "): lookups beyond the records' reach are traced instead (the stats' "
                    "lookups_answered); raise max_records to cache more");
    if (const std::string noisy = noisyRecordsWarning(scene, st.radianceCache); !noisy.empty())
        w.push_back(noisy);
    if (const std::string sky = compressedSkyWarning(st); !sky.empty()) w.push_back(sky);
    if (const std::string phase = compoundedPhaseWarning(scene, st.counters.phaseWeights);
        !phase.empty())
        w.push_back(phase);
    if (st.counters.nonFiniteSamples > 0)
        w.push_back(std::to_string(st.counters.nonFiniteSamples) +
                    " samples were NaN or infinite and were dropped");
    InvalidDraws invalid = st.counters.invalid;
    invalid.add(st.radianceCache.recordInvalid);
    if (invalid.total() > 0) w.push_back(invalidDrawsWarning(invalid));
    if (st.radianceCache.recordNonFinite > 0)
        w.push_back("render.radiance_cache: " + std::to_string(st.radianceCache.recordNonFinite) +
                    " record paths were NaN or infinite and were taken as 0");
    // A path ended by max_depth loses the light it would have gathered beyond: an albedo-1
    // furnace (σ_t 300, g 0.99) rendered 0.529 for 1 at the default depth without a word
    // (helper 61's audit). The radiance cache's record paths count too: with the cache, they
    // carry the light of every bounce after a camera path's first. Below depth 8 the cut is
    // taken as meant (single scattering is max_depth 1).
    // A share below 0.1% is said too once it exceeds the image mean's relative standard error
    // (of independent samples, which overstates a stratified render's): at many samples the loss
    // outgrows the noise (helper 82: an albedo-1 furnace at 1024 spp, 0.086% of its paths cut,
    // rendered 0.99914 ± 0.00006 for 1 without a word).
    const uint64_t paths = st.counters.paths + st.radianceCache.recordPaths,
                   truncated = st.counters.truncatedPaths + st.radianceCache.recordPathsTruncated;
    const double share = paths > 0 ? double(truncated) / double(paths) : 0,
                 relativeError = st.imageMeanRelativeError;
    const double surely = truncatedShareLowerBound(truncated, paths);
    if (scene.settings.maxDepth >= kTruncationWarningDepth &&
        (surely > kTruncatedPathsShare || surely > relativeError)) {
        char msg[400], beyondNoise[160] = "";
        if (surely <= kTruncatedPathsShare)
            std::snprintf(beyondNoise, sizeof beyondNoise,
                          ", more than the image mean's relative standard error (%.2g%%)",
                          100 * relativeError);
        std::snprintf(msg, sizeof msg,
                      "render.max_depth: %llu of %llu paths (%.3g%%) reached depth %d and were "
                      "ended there, without the light beyond it%s; raise render.max_depth",
                      (unsigned long long)truncated, (unsigned long long)paths, 100 * share,
                      scene.settings.maxDepth, beyondNoise);
        w.push_back(msg);
    }
    // The stated error rests on few degrees of freedom where a few pixels' rare large samples
    // hold the variance (helper 160: g 0.99 under media/sunsky.exr, a render 14% low stated
    // 0.56%, z = −25; milk_glass at 16 spp, mean z² 138; helper 162 found this statistic to tell
    // such renders apart, AUC 0.994).
    const double withinDof =
        double(scene.camera.width) * scene.camera.height * std::max(0.0, double(st.minSamples) - 1);
    if (st.imageMeanRelativeErrorDof < kFewErrorDof && withinDof >= kErrorDofWarnsFrom) {
        char msg[600];
        std::snprintf(msg, sizeof msg,
                      "image_mean_relative_error: %.2g%% rests on about %.2g degrees of freedom "
                      "(image_mean_relative_error_dof): a few pixels' large samples hold most of "
                      "its variance, so it is uncertain by a factor of %.2g or more, and far too "
                      "small where rarer samples are larger still (a heavy tail); render more "
                      "samples per pixel, or compare with a reference",
                      100 * st.imageMeanRelativeError, st.imageMeanRelativeErrorDof,
                      1 + std::sqrt(2 / st.imageMeanRelativeErrorDof));
        w.push_back(msg);
    }
    return w;
}

nlohmann::json invalidDrawsJson(const InvalidDraws& d) {
    nlohmann::json j = nlohmann::json::object();
    d.forEachSource([&](const char* key, const char*, uint64_t n) { j[key] = n; });
    return j;
}

/// Everything the stats file says about one image; `provenance` (inputs, overrides, command line,
/// machine) is merged in as it is.
nlohmann::json statsJson(const Scene& scene, const Image& image, const RenderStats& st,
                         const std::string& out, const std::vector<std::string>& warnings,
                         const nlohmann::json& provenance) {
    const PathCounters& c = st.counters;
    nlohmann::json j;
    j["shvol_version"] = SHVOL_VERSION;
    j["git_revision"] = gitRevision();
    j["scene"] = scene.path;
    j["output"] = out;
    j["resolution"] = {scene.camera.width, scene.camera.height};
    j["seed"] = st.seed;
    j["spp"] = st.spp;
    j["interrupted"] = st.stop == RenderStop::Cancelled;
    j["stopped_by"] = renderStopName(st.stop);
    j["samples_per_pixel_min"] = st.minSamples;
    j["samples_per_pixel_max"] = st.maxSamples;
    j["resumed_from_samples"] = st.resumedFromSamples;
    j["threads"] = st.threads;
    j["wall_time_s"] = st.wallSeconds;
    j["paths"] = c.paths;
    j["paths_per_second"] = st.pathsPerSecond();
    j["mean_path_length"] = st.meanPathLength();
    j["scattering_events"] = c.scatteringEvents;
    j["phase_samples"] = c.phaseSamples;
    j["light_samples"] = c.lightSamples;
    j["product_samples"] = c.productSamples;
    j["product_pdfs"] = c.productPdfs;
    j["transmittance_rays"] = c.transmittanceRays;
    j["density_lookups"] = c.tracking.densityLookups;
    j["density_lookups_per_second"] = c.tracking.densityLookups / std::max(1e-9, st.wallSeconds);
    j["majorant_segments"] = c.tracking.segments;
    j["exact_cells"] = c.tracking.exactCells;
    j["non_finite_samples"] = c.nonFiniteSamples;
    j["paths_truncated"] = c.truncatedPaths;
    // (only where a phase weight is not always 1: compoundedPhaseWarning)
    if (c.phaseWeights.count() > 0)
        j["phase_weight_second_moment_along_paths"] = c.phaseWeights.meanLowerBound();
    j["invalid_draws"] = invalidDrawsJson(c.invalid);
    // (null where unknown: no light, or a film resumed from a checkpoint without its squares)
    j["image_mean_relative_error"] = std::isfinite(st.imageMeanRelativeError)
                                         ? nlohmann::json(st.imageMeanRelativeError)
                                         : nlohmann::json(nullptr);
    // (null where it does not apply: at 1 spp, or where the error is unknown)
    j["image_mean_relative_error_dof"] = std::isfinite(st.imageMeanRelativeErrorDof)
                                             ? nlohmann::json(st.imageMeanRelativeErrorDof)
                                             : nlohmann::json(nullptr);
    if (const SurfaceScene* surf = scene.surfaces.get()) {
        nlohmann::json& sj = j["surfaces"];
        sj["count"] = surf->surfaces().size();
        sj["triangles"] = surf->triangleCount();
        size_t emitters = 0;
        for (const Surface& s : surf->surfaces()) emitters += s.emits();
        sj["emitters"] = emitters;
        sj["bvh_build_s"] = surf->buildSeconds();
        sj["ray_offset"] = surf->epsilon();
        sj["hits"] = c.surfaceHits;
        sj["bsdf_events"] = c.surfaceEvents;
        sj["area_light_samples"] = c.areaLightSamples;
        sj["shadow_rays"] = c.shadowRays;
    }
    if (const RadianceCacheStats& rc = st.radianceCache; rc.used) {
        nlohmann::json& cj = j["radiance_cache"];
        cj["records"] = rc.records;
        cj["memory_bytes"] = rc.memoryBytes;
        cj["brdf_table_bytes"] = rc.tableBytes;
        cj["brdf_table_s"] = rc.tableSeconds;
        double largest = 0, largestPeak = 0;
        for (const BrdfTableErrors& e : rc.tableErrors) {
            cj["brdf_table_projection_errors"][e.surface] = e.projection;
            cj["brdf_table_peak_errors"][e.surface] = e.peak;
            largest = std::max(largest, e.projection);
            largestPeak = std::max(largestPeak, e.peak);
        }
        cj["brdf_table_projection_error"] = largest;
        cj["brdf_table_peak_error"] = largestPeak;
        cj["uncached_surfaces"] = nlohmann::json::object();  // name → the table's albedo error
        for (const auto& [surface, error] : rc.uncached) cj["uncached_surfaces"][surface] = error;
        cj["fill_s"] = rc.fillSeconds;
        cj["record_paths"] = rc.recordPaths;
        cj["record_paths_truncated"] = rc.recordPathsTruncated;
        cj["record_non_finite_samples"] = rc.recordNonFinite;
        // (one ray, or no record, gives no error estimate: unknown, where 0 read as perfect
        // records; helpers 155, 156)
        const auto known = [&](double e) {
            return scene.settings.radianceCache.raysPerRecord >= 2 && rc.records > 0 ? Json(e)
                                                                                     : Json();
        };
        cj["record_irradiance_relative_error"] = {{"median", known(rc.recordErrorMedian)},
                                                  {"p90", known(rc.recordErrorP90)},
                                                  {"max", known(rc.recordErrorMax)}};
        cj["record_invalid_draws"] = invalidDrawsJson(rc.recordInvalid);
        cj["lookups"] = c.cacheLookups;
        cj["lookups_answered"] = c.cacheHits;
        cj["lookup_s"] = double(c.cacheLookupNs) * 1e-9;
    }
    j["peak_memory_mib"] = peakMemoryMiB();
    j["effects"] = st.effects;
    // (The effects named only what was on: why NEE was off under a sky went unsaid; helper 68.)
    const Effects effects = Effects::of(scene);
    j["next_event_estimation"] = {
        {"setting", scene.settings.nee ? nlohmann::json(*scene.settings.nee) : "auto"},
        {"environment", effects.nextEvent},
        {"area_lights", effects.areaLights},
        {"why", neeReason(scene, effects)}};
    if (!scene.environment.isConstant()) {
        j["next_event_estimation"]["sky_second_moment_ratio"] =
            scene.environment.secondMomentRatio();
        j["next_event_estimation"]["sky_brightest_share"] = scene.environment.peak().brightestShare;
    }
    j["roulette_threshold"] = st.rouletteThreshold;
    j["sampler"] = sampleStreamName(scene.settings.sampler);
    if (const LightSamplingStats& ls = st.lightSampling; !ls.strategy.empty()) {
        nlohmann::json& l = j["light_sampling"];
        l["strategy"] = ls.strategy;
        l["mis"] = ls.mis;
        l["setup_s"] = ls.setupSeconds;
        if (ls.skyResolution > 0) {
            l["sky_resolution"] = ls.skyResolution;
            l["sky_memory_bytes"] = ls.skyBytes;
            l["wavelet_coefficients_kept"] = ls.waveletKept;
            l["wavelet_coefficients_total"] = ls.waveletDetails;
            l["wavelet_relative_l2_error"] = ls.waveletL2Error;
            l["wavelet_light_second_moment"] = ls.waveletSecondMoment;
        }
        if (ls.productOrder > 0) {
            l["product_order"] = ls.productOrder;
            l["product_depth"] = ls.productDepth;
        }
    }
    j["media"] = nlohmann::json::array(), j["phase"] = nlohmann::json::array();  // [] without media
    for (const auto& m : scene.media) {
        j["media"].push_back(m->describe());
        j["phase"].push_back(phaseJson(m->phase()));
    }
    j["warnings"] = warnings;
    j.update(provenance);
    const ImageStatistics is = imageStatistics(image);
    auto rgb = [](const Spectrum& s) { return nlohmann::json{s[0], s[1], s[2]}; };
    j["image"] = {{"mean", rgb(is.mean)},
                  {"min", rgb(is.min)},
                  {"max", rgb(is.max)},
                  {"non_finite", is.nonFinite}};
    return j;
}

/// The files one image goes to: the EXR, its stats and (with --variance) the standard errors.
}  // namespace

Outputs outputsFor(const std::string& out, const std::string& tag) {
    const bool exr = hasExtension(out, ".exr");
    std::string stem = exr ? out.substr(0, out.size() - 4) : out;
    const std::string ext = exr ? out.substr(out.size() - 4) : ".exr";
    if (!tag.empty()) stem += "." + tag;
    return {stem + ext, stem + ".stats.json", stem + ".stderr" + ext};
}

namespace {

/// Whether o.stderrImage holds the standard errors of an earlier render of this image, which
/// would pass for this one's: the stats that render wrote under this name name it, and it is no
/// file this render reads (the scene's inputs, in `provenance`) or keeps (`checkpoint`).
bool staleStandardErrors(const Outputs& o, const nlohmann::json& provenance,
                         const std::string& checkpoint) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_regular_file(o.stderrImage, ec)) return false;
    const nlohmann::json old = parseOwnJsonFile(o.stats);
    // (by file name: the stats and the errors sit side by side, and the earlier render may have
    // named the directory otherwise, ./d/y.exr for d/y.exr; helper 88)
    if (!old.is_object() || !old.value("standard_error", nlohmann::json()).is_string() ||
        fs::path(old["standard_error"].get<std::string>()).filename() !=
            fs::path(o.stderrImage).filename())
        return false;
    std::vector<std::string> kept = {checkpoint};
    for (const nlohmann::json& in : provenance.value("inputs", nlohmann::json::array()))
        kept.push_back(in.value("path", std::string()));
    for (const std::string& k : kept)
        if (!k.empty() && fs::equivalent(k, o.stderrImage, ec)) return false;
    return true;
}

/// Writes an image with its statistics (and standard errors), together (writeTogether): all into
/// temporaries, then renamed one after another. Without standard errors, those an earlier render
/// of the image left are removed (staleStandardErrors; `checkpoint` is kept).
void writeOutputs(const Outputs& o, const Scene& scene, const Film& film, const RenderStats& st,
                  const std::vector<std::string>& warnings, const nlohmann::json& provenance,
                  bool variance, const std::string& checkpoint) {
    const Image image = film.image();
    const Image se = variance ? film.standardError() : Image();
    std::vector<std::string> all = warnings;
    for (const std::string& w : renderWarnings(scene, st)) all.push_back(w);
    // Warnings about this image's files: on stderr, naming the file, and in its statistics.
    const auto warn = [&](const std::string& file, const std::string& text) {
        all.push_back(text);
        std::fprintf(stderr, "shvol: warning: %s: %s\n", file.c_str(), text.c_str());
    };
    // A mean beyond the largest float (3.4·10³⁸) becomes ±inf in the float32 EXR: said, not
    // clamped (the value is not known to be the largest float either).
    const size_t overflows = size_t(std::count_if(image.rgb.begin(), image.rgb.end(),
                                                  [](float v) { return !std::isfinite(v); }));
    if (overflows > 0)
        warn(o.image, std::to_string(overflows) +
                          " pixel values exceed the float32 range of OpenEXR (3.4e38) and are "
                          "written as inf");
    const auto pixelsBelow = [&](uint32_t n) {
        return size_t(
            std::count_if(film.count.begin(), film.count.end(), [n](uint32_t c) { return c < n; }));
    };
    // Standard errors that overflow, of pixels that have the two samples an estimate needs (the
    // others are +inf as unknown, said below).
    size_t seOverflows = 0;
    for (size_t i = 0; i < se.rgb.size(); ++i)
        seOverflows += film.count[i / 3] >= 2 && !std::isfinite(se.rgb[i]);
    if (seOverflows > 0)
        warn(o.stderrImage, std::to_string(seOverflows) +
                                " standard errors exceed the float32 range of OpenEXR (3.4e38), or "
                                "their samples' squares the double range, and are written as inf");
    const std::string of = " of " + std::to_string(film.pixels()) + " pixels have ";
    if (const size_t empty = pixelsBelow(1); empty > 0)
        warn(o.image, std::to_string(empty) + of +
                          "no sample (the render stopped early) and are written as 0");
    if (const size_t unknown = pixelsBelow(2); variance && unknown > 0)
        warn(o.stderrImage, std::to_string(unknown) + of +
                                "fewer than 2 samples (the render stopped early); their standard "
                                "error is written as +inf (unknown)");
    const bool removeStale = !variance && staleStandardErrors(o, provenance, checkpoint);
    if (removeStale)
        warn(o.stderrImage,
             "removed: the standard errors of an earlier render of this image (this render has "
             "none; --variance writes them)");
    // The three appear together: a failure to write any of them, or a signal meanwhile, leaves
    // none, and a second Ctrl-C at their renames can no longer put the image beside the previous
    // render's statistics (a rename that itself fails leaves the ones before it, and says so).
    std::vector<FileWrite> files = {
        {o.image, [&](const std::string& tmp) { writeExrTo(tmp, image, o.image); }}};
    if (variance)
        files.push_back(
            {o.stderrImage, [&](const std::string& tmp) { writeExrTo(tmp, se, o.stderrImage); }});
    // (the temporary is made before the statistics are computed: Cli tests signal while it exists)
    files.push_back({o.stats, [&](const std::string& tmp) {
                         writeStreamTo(tmp, o.stats, "file", [&](std::ofstream& f) {
                             nlohmann::json j =
                                 statsJson(scene, image, st, o.image, all, provenance);
                             if (variance) j["standard_error"] = o.stderrImage;
                             const std::string text = dumpJson(j, 2) + "\n";
                             errno = 0;  // (the calls above may have set it)
                             f << text;
                         });
                     }});
    writeTogether(files);
    // Standard errors an earlier render left under this image's name would pass for this one's
    // (batch's z-test reads ref.stderr.exr beside a reference file): removed, and said (helper
    // 83: a render resumed without --variance left the last session's beside its image).
    std::error_code ec;
    if (removeStale && !std::filesystem::remove(o.stderrImage, ec) && ec)
        std::fprintf(stderr,
                     "shvol: warning: %s: cannot remove it (%s): it holds the standard errors of "
                     "an earlier render, not this one's\n",
                     o.stderrImage.c_str(), ec.message().c_str());
}

/// text with each number in it (12, 62.5, 1.5e-05) written '#'.
std::string numbersAsHashes(const std::string& text) {
    const auto digit = [&](size_t i) {
        return i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]));
    };
    std::string shape;
    for (size_t i = 0; i < text.size();) {
        if (!digit(i)) {
            shape += text[i++];
            continue;
        }
        shape += '#';
        while (digit(i) || (text[i] == '.' && digit(i + 1)) ||
               ((text[i] == 'e' || text[i] == 'E') &&
                (digit(i + 1) || ((text[i + 1] == '-' || text[i + 1] == '+') && digit(i + 2)))))
            i += digit(i) || text[i] == '.' ? 1 : digit(i + 1) ? 2 : 3;
    }
    return shape;
}

WarningSink& warningSink() {
    static WarningSink sink;
    return sink;
}
}  // namespace

void setWarningSink(WarningSink sink) {
    warningSink() = std::move(sink);
}

/// Prints "shvol: warning: SCENE: TEXT", or in a batch "shvol: warning: SCENE (run RUN): TEXT",
/// unless this process said TEXT of SCENE before, or another run said a TEXT that differs from it
/// in its numbers only: a batch's renders of one scene (repeats, other sample counts) give it the
/// same warnings, which each run's stats keep, and stderr says once, naming the first run that
/// gave it (it named none: a warning of one run among many could not be placed; helper 67). The
/// max_depth warning's counts differ from run to run, and an 80-run sweep said it for nearly every
/// run (helper 98); one run's warnings of media[0] and media[1] are two.
void warnOnce(const std::string& scene, const std::string& run, const std::string& text) {
    if (warningSink()) return warningSink()(scene, run, text);
    static std::mutex mutex;
    static std::set<std::string> said;                 // "SCENE: TEXT"
    static std::map<std::string, std::string> shapes;  // "SCENE: shape" → the run that said it
    const std::lock_guard<std::mutex> lock(mutex);
    if (!said.insert(scene + ": " + text).second) return;
    const auto [first, isNew] = shapes.emplace(scene + ": " + numbersAsHashes(text), run);
    if (!isNew && first->second != run) return;
    std::fprintf(stderr, "shvol: warning: %s%s: %s\n", scene.c_str(),
                 run.empty() ? "" : (" (run " + run + ")").c_str(), text.c_str());
}

namespace {

/// --spp: "N" or increasing "N1,N2,…,N" (each Ni an image of its own). Gives the list; when the
/// text is not one, says why in `problem` (and the list is not to be used).
std::vector<uint32_t> parseSppList(const std::string& text, std::string& problem) {
    std::vector<uint32_t> list;
    if (text.empty()) {
        problem = "expected N or N1,N2,...,N, got \"\"";
        return list;
    }
    // Every item between commas, empty ones too ("16," is refused like ",16").
    for (size_t from = 0, to = 0; to != std::string::npos; from = to + 1) {
        to = text.find(',', from);
        std::string item = text.substr(from, to == std::string::npos ? to : to - from);
        if (problem = integerIn(1, kMaxSpp)(item); !problem.empty()) return list;
        const uint32_t n = uint32_t(std::stoul(item));
        if (!list.empty() && n <= list.back()) {
            problem = "sample counts must increase, got " + text;
            return list;
        }
        list.push_back(n);
    }
    return list;
}

}  // namespace

int runRender(const RenderArgs& a) {
    // total_s in the stats: what the image cost, loading and building included (wall_time_s
    // counts the passes only; at HSH order 20 the cache's fill took 2.5× their time: helper 63).
    const auto started = std::chrono::steady_clock::now();
    const auto secondsSoFar = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    };
    const MpiWorld& world = MpiWorld::get();
    const bool spread = world.parallel() && !a.oneRank;  // the ranks share this render
    const bool speaks = !spread || world.root();
    Json doc;
    Scene scene;
    std::string out;
    Outputs final;
    std::vector<std::string> warnings;
    nlohmann::json provenance;
    Json identity;
    Film film;
    std::vector<uint32_t> stops;
    collectively(
        [&] {  // every rank reads the scene; a bad one fails on all of them alike
            if (spread) {
                if (a.timeLimit > 0 || !a.checkpoint.empty() || a.resume)
                    failOption(
                        a.timeLimit > 0 ? "--time-limit" : "--checkpoint",
                        "not available in a render over several MPI ranks (README.md, \"MPI\")");
            }
            std::string refused;  // (by --spp's validator already, for the command line)
            const std::vector<uint32_t> sppList =
                a.spp.empty() ? std::vector<uint32_t>{} : parseSppList(a.spp, refused);
            if (!refused.empty()) failOption("--spp", refused);
            // --spp and --seed are applied after every --set: one that sets the same key too
            // would have no effect, yet be recorded among the stats' overrides.
            for (const auto& [given, option, name] : {std::tuple{!sppList.empty(), "--spp", "spp"},
                                                      std::tuple{a.seed >= 0, "--seed", "seed"}})
                if (const std::string* set =
                        given ? overrideSetting(a.sets, {"render", name}) : nullptr)
                    failOption(option, "--set " + *set + " sets the same value; give it once");
            nlohmann::json resolved;
            std::vector<std::string> unchanged;  // (key=null of a key the scene does not have)
            Json original;               // (the file's own document, for the errors of a --set)
            std::vector<int> removedBy;  // (a --set's value that a later one removed)
            doc = sceneDocument(a.scene, a.sets, &unchanged, &original, &removedBy);  // read once
            // --spp and --seed after the overrides, into a "render" object only: a scene or a
            // --set whose "render" is something else is refused by the reader as such, not
            // blamed on these options.
            if (doc.is_object() && (!doc.contains("render") || doc["render"].is_object())) {
                if (!sppList.empty()) doc["render"]["spp"] = sppList.back();
                if (a.seed >= 0) doc["render"]["seed"] = a.seed;
            }
            try {
                scene = sceneFromJson(doc, a.scene, &resolved);
            } catch (const Error& e) {
                // A --set that misspells a key or gives a value the scene refuses is named, not
                // the scene (helpers 127, 133).
                std::string reason;
                if (const int i =
                        overrideOfError(e.what(), a.scene, original, doc, a.sets, &reason);
                    i >= 0)
                    fail(a.scene, overridePlace(a.sets[size_t(i)]), reason);
                throw;
            }
            out = a.output;
            if (out.empty()) out = std::filesystem::path(a.scene).stem().string() + ".exr";
            // (-o is checked as it is parsed; the default, <scene name>.exr, here.)
            if (const std::string problem = outputNameProblem(out, ".exr", kRenderWritesExr);
                !problem.empty())
                fail(out, "", problem);
            final = outputsFor(out, "");
            warnings = phaseWarnings(scene);
            for (const std::string& set : unchanged)
                warnings.push_back("--set " + set +
                                   ": the scene has no such key; nothing was deleted");
            // (not in a batch, whose overrides are its sweep's `set` and axes, in an order the
            // sweep does not choose; helper 140)
            for (size_t i = 0; a.run.empty() && i < removedBy.size(); ++i)
                if (const int j = removedBy[i]; j >= 0) {
                    const std::string& later = a.sets[size_t(j)];
                    const std::string key = later.substr(0, later.find('='));
                    const bool type =
                        key.size() > 5 && key.compare(key.size() - 5, 5, ".type") == 0;
                    warnings.push_back(overridePlace(a.sets[i]) + ": not used: the later " +
                                       overridePlace(later) +
                                       (type ? " starts its object afresh with a new type"
                                             : " replaces or deletes its object") +
                                       "; give it after that one");
                }
            for (std::string& w : surfaceWarnings(scene)) warnings.push_back(std::move(w));
            // A grid with no density above 0 (all zeros, or a wrong grid): the medium is empty.
            for (size_t i = 0; i < scene.media.size(); ++i)
                if (const Bounds3 b = scene.media[i]->bounds();
                    !(b.lo.array() <= b.hi.array()).all())
                    warnings.push_back("media[" + std::to_string(i) +
                                       "] is empty: no voxel of its grid is above 0 (" +
                                       scene.media[i]->describe() + ")");
            const Effects effects = Effects::of(scene);
            if (scene.settings.radianceCache.enabled &&
                scene.settings.radianceCache.maxRecords > 0 && !effects.radianceCache)
                warnings.push_back(
                    "render.radiance_cache: enabled, but no surface has a BSDF the cache holds "
                    "(lambert, phong, ward), or max_depth is 0: the render runs without it");
            if (const std::string w = unusedLightSamplingWarning(scene, effects); !w.empty())
                warnings.push_back(w);
            if (const std::string w = unusedMisWarning(scene, effects); !w.empty())
                warnings.push_back(w);
            if (const std::string w = fewRaysPerRecordWarning(scene, effects); !w.empty())
                warnings.push_back(w);
            if (const std::string w = unusedWaveletWarning(scene, effects); !w.empty())
                warnings.push_back(w);
            for (std::string& w : unusedKeyWarnings(doc, scene, effects))
                warnings.push_back(std::move(w));
            if (const std::string w = misNoneWarning(scene, effects); !w.empty())
                warnings.push_back(w);
            if (const std::string w = neeOffPeakWarning(scene, effects); !w.empty())
                warnings.push_back(w);
            // Every sample of a pixel reads the same records, so the spread of its samples does
            // not hold their error (helper 80: z-scores up to 32.6 against a path-traced
            // reference on milk_glass at the default 1024 rays per record).
            // (A cache of max_records 0 is off: the errors are those of a render without it;
            // helper 83.)
            if (a.variance && effects.radianceCache)
                warnings.push_back(
                    "--variance: the standard errors leave out the radiance cache's own error, "
                    "which every sample of a pixel shares: they can be far too small (a z-test "
                    "against a path-traced reference fails where the records are noisy)");
            // The resolved scene leaves out the keys this render does not use (the defaults of
            // effects that are off), which a render of it would warn of (helper 139: every
            // render of a stats file's scene_resolved warned of product_order, product_depth and
            // five radiance-cache keys no one gave).
            Json used = resolved;
            std::vector<std::string> unusedKeys;
            unusedKeyWarnings(resolved, scene, effects, &unusedKeys);
            for (const std::string& key : unusedKeys) {
                const Json::json_pointer pointer(key);
                used.at(pointer.parent_pointer()).erase(pointer.back());
            }
            provenance = {{"scene_resolved", used},
                          {"inputs", inputFiles(doc, a.scene)},
                          {"overrides", a.sets},
                          {"command_line", commandLine()},
                          {"machine", machineDescription()},
                          {"mpi_ranks", spread ? world.size() : 1}};
            // The scene as the loader read it, defaults written out: a value given as its default
            // (--seed 1, render.rr_depth=3) is the same render as one left out; and as the stats
            // hold it, without the keys it does not use, so that the stats' scene resumes it
            // (helper 140: an unused product_order of 6 refused it).
            if (!a.checkpoint.empty())
                identity = renderIdentity(used, provenance.at("inputs"), gitRevision());
            // (a missing one named neither option: "nock.bin: no such file"; helper 77)
            if (a.resume)
                if (const std::string problem = inputFileProblem(a.checkpoint); !problem.empty())
                    failOption("--checkpoint",
                               a.checkpoint + ": " + problem + ": --resume continues it");
            if (a.resume) try {
                    film = readCheckpoint(a.checkpoint, identity);
                } catch (const Error& e) {
                    if (!a.checkpointOptional) throw;
                    warnings.push_back(std::string(e.what()) +
                                       ": the checkpoint is not resumed; the render starts afresh");
                }
            // The checkpoint's temporaries that a render killed while it wrote one left (a
            // checkpoint's size each; helper 147).
            if (!a.checkpoint.empty()) {
                const std::filesystem::path target = linkTarget(a.checkpoint);
                removeStaleTemporaries(
                    target.parent_path().empty() ? "." : target.parent_path().string(),
                    [&](const std::string& name) { return name == target.filename().string(); });
            }
            if (a.variance && film.maxCount() > 0 && film.sumSq.empty())
                fail(a.checkpoint, "",
                     "was saved without --variance, so the standard errors of its samples are "
                     "lost; resume without --variance, or start afresh");
            if (film.maxCount() > uint32_t(scene.settings.spp))
                fail(a.checkpoint, "",
                     "has " + std::to_string(film.maxCount()) +
                         " samples per pixel, more than the " + std::to_string(scene.settings.spp) +
                         " asked for; resume with at least that many (--spp)");
            if (sppList.size() > 1) stops.assign(sppList.begin(), sppList.end() - 1);
            // A resumed film with a pixel past an image asked for cannot give that image (a
            // render of n spp): say so, and leave it out, rather than write nothing or a mix.
            const auto past = [&](uint32_t n) {
                return n < film.maxCount() || n <= film.minCount();
            };
            for (const uint32_t n : stops)
                if (past(n))
                    warnings.push_back("--spp " + std::to_string(n) + ": the checkpoint " +
                                       a.checkpoint + " already holds up to " +
                                       std::to_string(film.maxCount()) +
                                       " samples per pixel; the image at " + std::to_string(n) +
                                       " spp is not written");
            stops.erase(std::remove_if(stops.begin(), stops.end(), past), stops.end());
            // Every file the render writes, with what it is.
            std::vector<std::pair<std::string, std::string>> writes = {
                {final.image, "the image"}, {final.stats, "the statistics"}};
            for (const uint32_t n : stops) {
                const Outputs o = outputsFor(out, "spp" + std::to_string(n));
                const std::string at = " at " + std::to_string(n) + " spp";
                writes.insert(writes.end(),
                              {{o.image, "the image" + at}, {o.stats, "the statistics" + at}});
                if (a.variance) writes.push_back({o.stderrImage, "the standard errors" + at});
            }
            if (a.variance) writes.push_back({final.stderrImage, "the standard errors"});
            if (!a.checkpoint.empty()) writes.push_back({a.checkpoint, "the checkpoint"});
            // Fail before rendering, not after, if an output cannot be written, would replace a
            // file the render reads (a sky written over by its render) or another output (a
            // checkpoint named as the image).
            // Named by the option that names the file: --checkpoint, or --output (the image and
            // the files named after it).
            for (size_t i = 0; i < writes.size(); ++i) {
                const std::string& w = writes[i].first;
                const char* option =
                    !a.checkpoint.empty() && i + 1 == writes.size() ? "--checkpoint" : "--output";
                if (const std::string problem = outputFileProblem(w); !problem.empty())
                    failOption(option, w + ": cannot write: " + problem);
                for (const Json& in : provenance.at("inputs"))
                    if (sameFile(w, in.at("path").get<std::string>())) {
                        const std::string key = in.at("key").get<std::string>();
                        failOption(option, w + ": " +
                                               (key == "(scene)"
                                                    ? std::string("is the scene file")
                                                    : "is an input of the scene (" + key + ")") +
                                               "; write the output elsewhere");
                    }
                for (size_t k = 0; k < i; ++k)
                    if (sameFile(w, writes[k].first))
                        failOption(option, w + ": " + writes[i].second + " would be written over " +
                                               writes[k].second + "; give each a file of its own");
            }
            if (a.variance &&
                std::min(stops.empty() ? 2 : stops.front(), uint32_t(scene.settings.spp)) < 2)
                failOption(
                    "--variance",
                    "a standard error needs at least 2 samples per pixel, and the render would "
                    "write an image of 1");
        },
        spread);
    if (speaks)
        for (const std::string& w : warnings) warnOnce(a.scene, a.run, w);

    const uint32_t spp = uint32_t(scene.settings.spp);
    RenderOptions opt;
    opt.threads = a.threads > 0 ? a.threads : spread ? threadsPerRender(1) : 0;
    if (const std::string w = bindingWarning(opt.threads > 0 ? opt.threads : threadsPerRender(1));
        speaks && a.threads == 0 && !w.empty())
        std::fprintf(stderr, "shvol: warning: %s\n", w.c_str());
    opt.progress = !a.quiet && speaks && Progress::stderrIsTerminal();
    // Under mpirun a signal ends the ranks at once (nothing is half-written: outputs are atomic).
    opt.cancel = spread ? nullptr : &InterruptGuard::interrupted();
    opt.timeLimitSeconds = a.timeLimit;
    opt.variance = a.variance;
    opt.stops = stops;
    // Passes double, so the last would hold half a long render's time without a checkpoint.
    if (!a.checkpoint.empty()) opt.maxPassSeconds = a.checkpointInterval;
    opt.part = spread ? world.rank() : 0;
    opt.parts = spread ? world.size() : 1;
    auto lastCheckpoint = std::chrono::steady_clock::now();
    // Saves the film in the checkpoint; an optional one that cannot be written is warned of once,
    // and no more are written. `last`: the save at a stop, after which nothing goes on.
    bool checkpointing = !a.checkpoint.empty();
    const auto saveCheckpoint = [&](const Film& f, bool last) {
        if (!checkpointing) return;
        try {
            writeCheckpoint(a.checkpoint, f, identity);
        } catch (const Error& e) {
            if (!a.checkpointOptional) throw;
            checkpointing = false;
            // (at a stop it said the render went on, helper 156; an earlier save stays in place,
            // helper 158)
            const bool earlier = std::filesystem::exists(a.checkpoint);
            warnings.push_back(
                std::string(e.what()) +
                (!last     ? ": no more checkpoints are written; the render goes on without them"
                 : earlier ? ": the samples since the checkpoint's last save are not kept; the "
                             "next start resumes from that save"
                           : ": the samples so far are not kept; the next start begins afresh"));
            warnOnce(a.scene, a.run, warnings.back());
        }
    };
    opt.afterPass = [&](const Film& f, const RenderStats& st) {
        const uint32_t n = st.passEnd;
        if (n < spp && std::find(opt.stops.begin(), opt.stops.end(), n) != opt.stops.end()) {
            // Over MPI ranks a copy is reduced: the rank's own film goes on rendering.
            Film reduced;
            RenderStats stats = st;
            if (spread) {
                reduced = f;
                world.reduceToRoot(reduced, stats);
            }
            if (!speaks) return;
            // The image is that of a render of n samples, and its stats say so.
            stats.spp = int(n);
            nlohmann::json asked = provenance;
            asked["scene_resolved"]["render"]["spp"] = n;
            asked["total_s"] = secondsSoFar();
            const Outputs o = outputsFor(out, "spp" + std::to_string(n));
            try {
                writeOutputs(o, scene, spread ? reduced : f, stats, warnings, asked, a.variance,
                             a.checkpoint);
            } catch (const std::exception& e) {
                // The other ranks render on, and would wait for this one at the next image or
                // the final reduction for ever (a directory gone, a full disk; helper 71): the
                // error ends them all.
                if (!spread) throw;
                std::fprintf(stderr, "%s\n", errorLine(e).c_str());
                MpiWorld::abort(1);
            }
            // (its stats and standard errors too, as the final line names them; helper 77)
            if (!a.quiet)
                std::fprintf(stderr, "wrote %s%s and %s (%u spp)\n", o.image.c_str(),
                             a.variance ? (", " + o.stderrImage).c_str() : "", o.stats.c_str(), n);
        }
        const auto now = std::chrono::steady_clock::now();
        if ((n == spp && !a.checkpointOptional) ||
            (n < spp &&
             std::chrono::duration<double>(now - lastCheckpoint).count() >= a.checkpointInterval)) {
            saveCheckpoint(f, false);
            lastCheckpoint = now;
        }
    };
    // The guard lives until the outputs are written: a first signal while they are written is
    // taken as one during the render (the outputs complete, exit code 128 + the signal), not as the
    // default action that ended the process with none of them.
    std::optional<InterruptGuard> guard;
    if (!spread) guard.emplace();
    RenderResult r = render(scene, opt, std::move(film));
    if (spread) world.reduceToRoot(r.film, r.stats);
    if (!speaks) return 0;
    const bool interrupted = r.stats.stop == RenderStop::Cancelled;
    // A batch's run stopped before its first sample writes nothing: its image would be black and
    // its stats of no samples, and it renders again at the next start (helper 159: a --jobs 2
    // batch stopped left such files beside the finished runs').
    if (interrupted && !a.run.empty() && r.stats.maxSamples == 0) {
        std::fprintf(stderr, "shvol: interrupted before the first sample of %s: nothing written\n",
                     final.image.c_str());
        return InterruptGuard::stopExitCode();
    }
    // A render that stopped early has no closing afterPass call: save where it stopped.
    if (r.stats.stop != RenderStop::Completed) saveCheckpoint(r.film, true);
    provenance["total_s"] = secondsSoFar();
    // The images of --spp N1,… that a stop came before (each is written at its pass's end), said
    // on stderr and in the stats (they were on stderr only; helper 71).
    std::vector<std::string> finalWarnings = warnings, notWritten;
    for (const uint32_t n : stops)
        if (r.stats.stop != RenderStop::Completed && n > r.stats.passEnd && n < spp)
            notWritten.push_back("--spp " + std::to_string(n) + ": the render stopped before " +
                                 std::to_string(n) +
                                 " samples per pixel; that image is not written");
    finalWarnings.insert(finalWarnings.end(), notWritten.begin(), notWritten.end());
    writeOutputs(final, scene, r.film, r.stats, finalWarnings, provenance, a.variance,
                 a.checkpoint);
    if (r.stats.stop != RenderStop::Completed)
        std::fprintf(stderr,
                     "shvol: %s: wrote the samples finished so far to %s (%u to %u per pixel of "
                     "%d)%s\n",
                     interrupted ? "interrupted" : "time limit reached", final.image.c_str(),
                     r.stats.minSamples, r.stats.maxSamples, scene.settings.spp,
                     // (a batch's reference resumes when the batch is run again)
                     a.checkpoint.empty() || !a.run.empty() ? "" : "; continue with --resume");
    // (named by the scene, as every other warning of a render: helper 77)
    for (const std::string& w : notWritten) warnOnce(a.scene, a.run, w);
    for (const std::string& w : renderWarnings(scene, r.stats)) warnOnce(a.scene, a.run, w);
    if (!a.quiet)
        // (Both times: the passes' alone made a render spent in an SH fit read "0.00 s"; the
        // stats' total_s, helper 122.)
        std::fprintf(stderr,
                     "wrote %s%s and %s (%.2f s of rendering, %.2f s in all, %.3g paths/s, "
                     "%s%d thread%s)\n",
                     final.image.c_str(), a.variance ? (", " + final.stderrImage).c_str() : "",
                     final.stats.c_str(), r.stats.wallSeconds, provenance["total_s"].get<double>(),
                     r.stats.pathsPerSecond(),
                     spread ? (std::to_string(world.size()) + " ranks of ").c_str() : "",
                     r.stats.threads, r.stats.threads == 1 ? "" : "s");
    if (!interrupted && guard && InterruptGuard::interrupted() && a.lateSignalStops) {
        std::fprintf(stderr,
                     "shvol: interrupted while the outputs were written; they are written whole\n");
        return InterruptGuard::stopExitCode();
    }
    return interrupted ? InterruptGuard::stopExitCode() : 0;
}

void addRenderCommand(CLI::App& app, std::function<int()>& run) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* c = app.add_subcommand("render", "Render a scene to a float32 EXR and a stats JSON");
    c->add_option("scene", args->scene, "Scene file (JSON)")
        ->required()
        ->check(nonEmptyName())
        ->check(notAStrayOverride());
    c->add_option("-o,--output", args->output,
                  "Output EXR (default: <scene name>.exr); statistics go to NAME.stats.json for -o "
                  "NAME.exr")
        ->check(outputNamed(".exr", kRenderWritesExr));
    c->add_option("--spp", args->spp,
                  "Samples per pixel (overrides render.spp); N1,N2,...,N also writes the image "
                  "at each Ni as <output>.sppNi.exr, identical to a render of Ni spp")
        ->check(CLI::Validator(
            [](std::string& text) {
                std::string problem;
                parseSppList(text, problem);
                return problem;
            },
            "N|N1,N2,..."))
        ->default_str("the scene's render.spp");
    c->add_flag("--variance", args->variance,
                "Also write the standard error of each pixel's mean to <output>.stderr.exr");
    c->add_option("--seed", args->seed, "Random seed (overrides render.seed)")
        ->transform(integerIn(0, kMaxSeed))
        ->default_str("the scene's render.seed");
    c->add_option("--threads", args->threads, "Worker threads (0: all cores)")
        ->transform(integerIn(0, 4096));
    addSetOption(c, args->sets);
    c->add_flag("--quiet", args->quiet, "No progress bar or summary");
    c->add_option("--time-limit", args->timeLimit,
                  "Stop after this many seconds of rendering and write what is finished")
        ->check(numberIn(0, 1e9, true))
        ->default_str("none");
    // An empty name (a script's unset variable) would save nothing and be found out only at
    // --resume; the options that act on a checkpoint are refused without one.
    CLI::Option* checkpoint =
        c->add_option("--checkpoint", args->checkpoint,
                      "Save the progress to FILE between passes, on interruption and at the end")
            ->check(CLI::Validator(
                [](std::string& path) {
                    return path.empty() ? std::string("needs a file name") : writableOutput()(path);
                },
                "FILE"));
    c->add_option("--checkpoint-interval", args->checkpointInterval,
                  "Seconds between checkpoints (written at the end of a pass; passes are "
                  "kept about this long)")
        ->check(numberIn(0, 1e9))
        ->needs(checkpoint);
    c->add_flag("--resume", args->resume,
                "Continue the render saved in --checkpoint (same scene, --set and seed; the "
                "sample count may grow)")
        ->needs(checkpoint);
    c->callback([&run, args] { run = [args] { return runRender(*args); }; });
}

}  // namespace shvol::app
