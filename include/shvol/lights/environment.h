#pragma once
/// \file Distant environment light: a constant radiance or a lat-long (equirectangular) map,
/// importance sampled by luminance (pbrt-v3 §14.2.4, "Infinite Area Lights").
///
/// Directions: w is the direction of a ray that escapes the scene (pointing from the scene
/// towards the environment); Le(w) is the radiance arriving back along −w.
///
/// Lat-long convention (z up, DESIGN.md angles; lights/latlong.h):
///   column x ↔ u ∈ [x/W, (x+1)/W), image φ = π − 2πu (Blender, the default) or 2πu (Shvol);
///   row y    ↔ θ ∈ [πy/H, π(y+1)/H),       centre θ = π(y + ½)/H; row 0 (top) looks up +z.
///   The map is rotated about +z by rotationDegrees: world φ = φ_img + rotation.
/// Lookup is nearest pixel (piecewise constant) times scale.
///
/// Sampling an image: a TexelSampler (sampling/texel_sampler.h) over (u, v) = (x/W, θ/π) with
/// weights
///   w(x, y) = Y(x, y) · sin θ_y · a_y,
/// Y the Rec. 709 luminance (0.2126 R + 0.7152 G + 0.0722 B, clamped at 0), θ_y the row centre,
/// and a_y = 1 except with lowerHemisphereBlack, where a_y is the fraction of the row above the
/// horizon (0 for rows entirely below it, so those rows are never sampled). The density over
/// solid angle follows from dω = sin θ dθ |dφ| = 2π² sin θ du dv:
///   pdf_ω(w) = pdf_uv(u, v) / (2π² sin θ)   (0 where sin θ = 0, at the exact poles).
/// pdf > 0 wherever Le > 0 (except the poles), which keeps the estimators unbiased. A row that
/// straddles the horizon (odd H) may produce samples just below it; they carry Le = 0.
/// Constant radiance: uniform sphere sampling, or the uniform upper hemisphere (z ≥ 0) when
/// lowerHemisphereBlack. With lowerHemisphereBlack, Le(w) = 0 for w.z < 0.
#include <memory>

#include "shvol/core/image.h"
#include "shvol/core/math.h"
#include "shvol/lights/latlong.h"
#include "shvol/lights/sky_hierarchy.h"
#include "shvol/sampling/texel_sampler.h"

namespace shvol {

/// wi: direction of the escaping ray (towards the environment); Le: radiance along it;
/// pdf: solid-angle density of wi (0 if nothing could be sampled, then Le = 0 too).
struct LightSample {
    Vec3 wi;
    Spectrum Le;
    double pdf;
};

class Environment {
  public:
    /// Constant radiance L in every direction (or only for z ≥ 0).
    static Environment constant(const Spectrum& L, bool lowerHemisphereBlack);
    /// Lat-long map; its importance distribution is built by prepareSampling() or the first
    /// sample() or pdf() (a render that draws no light sample from the sky never builds it).
    /// Throws shvol::Error if the image is empty. \param scale multiplies every pixel. \param
    /// rotationDegrees about +z.
    static Environment image(Image img, double scale, double rotationDegrees,
                             bool lowerHemisphereBlack,
                             LatLongMapping mapping = LatLongMapping::Blender);

    /// Radiance seen along an escaping ray with direction w (w need not be normalised).
    Spectrum Le(const Vec3& w) const;
    /// Builds an image's sampling tables now, which sample() and pdf() otherwise build at their
    /// first call (a render builds them before its passes when it draws light samples from the
    /// sky; VolumePathIntegrator).
    void prepareSampling() const {
        if (image_) texels();
    }
    /// Importance-sampled direction; see the file comment. \param u uniform in [0, 1)².
    LightSample sample(const Vec2& u) const;
    /// Solid-angle density of sample() producing w.
    double pdf(const Vec3& w) const;
    bool isConstant() const { return !image_; }
    /// The constant radiance (meaningful when isConstant()).
    Spectrum constantRadiance() const { return L_; }
    /// The same radiance in every direction (but below the horizon with lowerHemisphereBlack):
    /// a constant, or an image of equal pixels, for which next-event estimation does not pay
    /// any more than under a constant (Effects; helper 68: 7× less efficient there).
    bool uniform() const { return uniform_; }
    /// No light at all: a constant of 0, an image of zeros, or a scale of 0.
    bool black() const { return black_; }
    /// m = 4π ∫ Y² dω / (∫ Y dω)² over the sphere (Y the luminance, texel by texel, 0 below the
    /// horizon with lowerHemisphereBlack): 1 for a sky of equal radiance, 1 + the squared
    /// coefficient of variation of Y over directions drawn evenly over the sphere, which is the
    /// relative variance of the sky's light as sampled without regard to it (by an isotropic phase
    /// function; helper 186: over the directions seen only, a sky of black lower-half pixels and
    /// the same sky with lowerHemisphereBlack were judged apart). A sun of solid angle Ω_s holding
    /// a share f of the light gives about 4π f² / Ω_s. 1 for a constant or black sky.
    double secondMomentRatio() const { return secondMomentRatio_; }
    /// The largest channel value of the texels seen, before the scale (below the horizon left
    /// out with lowerHemisphereBlack); of a constant, its largest channel.
    double brightestSeen() const { return brightest_; }
    /// The part of the sky that dominates the variance of directions drawn without regard to it
    /// (by a phase function or a BSDF, next-event estimation off): its brightest directions that
    /// together hold half of ∫ Y² dω over the directions seen (Y the luminance), as their solid
    /// angle and their share of the power ∫ Y dω; texels are taken by luminance in bins of 1/64
    /// of an octave, the last one in part. A constant: half the solid angle seen, half the
    /// power. Zero for a black sky.
    struct Peak {
        double solidAngle = 0, powerShare = 0;
        /// The share of the light in the brightest directions that make up kSunSolidAngle of the
        /// directions seen (kSunSolidAngle for even light).
        double brightestShare = 0;
    };
    /// (Computed once per image, then kept; copies share it.)
    Peak peak() const;
    /// A sun: a peak under kSunSolidAngle of the directions seen that holds at least kSunShare of
    /// the sky's light. Directions drawn without regard to the sky meet it rarely, and miss most
    /// of its light at a few samples per pixel. (Without the solid-angle bound the circumsolar glow
    /// of make-sky's Preetham sky without a sun, 7.3% of the sky holding 26% of its light,
    /// counted.)
    bool hasSun() const;
    static constexpr double kSunSolidAngle = 0.01, kSunShare = 0.05;
    bool lowerHemisphereBlack() const { return lowerBlack_; }
    /// Rotation about +z in radians.
    double rotation() const { return rotation_; }
    LatLongMapping mapping() const { return mapping_; }
    /// The sky on the equal-area square (luminance, exact cell averages), for the wavelet and
    /// product samplers; K wavelet details kept (0 = all).
    SkyHierarchy skyHierarchy(size_t waveletCoefficients = 0) const;

  private:
    Environment() = default;
    /// (u, v) = (x/W, θ/π) of a unit direction, and sin θ.
    Vec2 toUv(const Vec3& w, double* sinTheta) const;
    /// Le of a texel whose RGB is rgb, seen along w (0 below the horizon with
    /// lowerHemisphereBlack).
    Spectrum texelRadiance(const Spectrum& rgb, const Vec3& w) const;
    /// The image's TexelSampler, built by the first caller (others wait for it).
    const TexelSampler& texels() const;

    Spectrum L_ = Spectrum::Zero();
    bool lowerBlack_ = false, uniform_ = true, black_ = true;
    double scale_ = 1, rotation_ = 0, brightest_ = 0, secondMomentRatio_ = 1;
    LatLongMapping mapping_ = LatLongMapping::Blender;
    std::shared_ptr<const Image> image_;  // null for a constant environment
    struct LazyTexels;
    std::shared_ptr<LazyTexels> texels_;  // null for a constant environment
    struct LazyPeak;
    std::shared_ptr<LazyPeak> peak_;  // null for a constant environment
    Peak computePeak() const;
};

}  // namespace shvol
