#pragma once
/// \file Procedural densities and skies for `shvol make-medium` and `shvol make-sky`.
#include <cstdint>
#include <optional>
#include <string>

#include "shvol/core/image.h"
#include "shvol/core/math.h"
#include "shvol/lights/latlong.h"

namespace shvol {

/// Gradient noise (Perlin 2002, "Improving Noise": quintic fade, hashed gradients) in [−1, 1].
double gradientNoise(const Vec3& p, uint64_t seed);

/// Fractional Brownian motion: Σ_k gain^k · noise(lacunarity^k · p), k < octaves.
double fbm(const Vec3& p, uint64_t seed, int octaves, double lacunarity = 2.0, double gain = 0.5);

struct CloudParams {
    uint64_t seed = 1;
    int octaves = 5;
    double frequency = 4;   ///< base noise frequency over the unit cube
    double coverage = 0.1;  ///< density = max(0, fbm + coverage − falloff)·sharpness
    double sharpness = 4;
};

/// A cumulus-like cloud in the cube [−½, ½]³: fBm noise shaped by a soft ellipsoidal falloff,
/// zero outside radius ½. Values are non-negative and at most about 1.
double cloudDensity(const Vec3& p, const CloudParams& params);

/// A rising smoke plume in the cube [−½, ½]³: a column from the floor to the top whose radius
/// grows from 0.02 to 0.11 with height, drifting sideways and displaced by fBm turbulence that
/// grows with height, with a smooth radial profile and fBm texture. It fills about 14% of its own
/// bounding box: the sparse scene of the majorant-grid benchmarks. Values are in [0, 1].
double plumeDensity(const Vec3& p, uint64_t seed);

/// A sphere of radius r and density 1 with a smooth edge one voxel wide.
double sphereDensity(const Vec3& p, double radius, double edge);

// ---------------------------------------------------------------------------------------------
// Skies for `shvol make-sky`.
//
// Units: the Preetham sky and its sun are in kcd/m² (kilocandela per square metre) of luminance:
// the linear Rec. 709 RGB triples below have luminance 0.2126 R + 0.7152 G + 0.0722 B equal to
// the CIE Y of the model in kcd/m², so a clear-sky zenith is a few units and the sun ~10⁶.
// ---------------------------------------------------------------------------------------------

enum class SkyModel {
    Simple,   ///< shvol 0.1's gradient sky (arbitrary units), kept unchanged
    Preetham  ///< Preetham, Shirley & Smits 1999 clear sky with a physical sun
};
/// "simple" or "preetham"; throws shvol::Error otherwise.
SkyModel skyModelFromName(const std::string& name);
const char* skyModelName(SkyModel m);

/// The sun's mean angular radius, 0.53°/2, in radians.
inline constexpr double TrueSunAngularRadius = 0.004625;
/// Solid angle of a disc (spherical cap) of angular radius r: 2π(1 − cos r) = 4π sin²(r/2) (the
/// latter keeps its precision for tiny r).
inline double capSolidAngle(double r) {
    const double s = std::sin(0.5 * r);
    return FourPi * s * s;
}
/// Projected solid angle of a disc (spherical cap) of angular radius r about the normal,
/// ∫ cos θ dω = π sin² r: the illuminance of a surface facing a disc of unit radiance.
inline double capProjectedSolidAngle(double r) {
    const double s = std::sin(r);
    return Pi * s * s;
}
/// Projected solid angle above the horizon, ∫ max(0, ω_z) dω, of a disc (spherical cap) of
/// angular radius r ∈ (0, π/2) whose centre has elevation e: the horizontal irradiance under the
/// disc at unit radiance, its part below the horizon hidden. With θ = π/2 − e, the centre's
/// zenith angle: π sin²r cos θ when the disc is wholly above (cos θ ≥ sin r), 0 wholly below
/// (cos θ ≤ −sin r), and in between, with x = cot r and y = −x cot θ ∈ (−1, 1),
///   sin²r (cos θ arccos y − x sin θ √(1 − y²)) + arctan(sin θ √(1 − y²) / x)
/// (the form factor of a sphere cut by the horizon: Snyder 1996, "Area light sources for
/// real-time graphics", MSR-TR-96-11; as written in Lagarde & de Rousiers 2014, "Moving
/// Frostbite to PBR", §4.7.2). The two ends meet the whole-disc values continuously.
double capProjectedSolidAngleAboveHorizon(double r, double e);
/// Mean luminance of the solar disc outside the atmosphere at the mean Sun–Earth distance, in
/// kcd/m²: 193 000 ± 4000 cd/cm² = 1.93·10⁹ cd/m² ("Luminance of the Sun", J. Opt. Soc. Am.
/// 45(6):483–488, 1955, doi:10.1364/JOSA.45.000483, extrapolated to zero air mass and averaged
/// over the limb-darkened disc). Cross-check: a luminous solar constant of 128–133 klx spread
/// over the disc's 6.72·10⁻⁵ sr gives 1.90–1.98·10⁹ cd/m². (The often quoted 1.6·10⁹ cd/m² is
/// the sun seen from the ground at noon, i.e. after the atmosphere; this model gives 1.57·10⁹
/// for a zenith sun and T = 2.)
inline constexpr double ExtraterrestrialSunLuminance = 1.93e6;

/// Relative optical air mass of Kasten & Young 1989 ("Revised optical air mass tables and
/// approximation formula", Applied Optics 28(22):4735–4738), for a solar elevation h in
/// radians (clamped at 0; no refraction correction):
///   m(h) = 1 / (sin h + 0.50572 (h° + 6.07995)^−1.6364),  h° = h in degrees.
/// m(90°) = 1, m(0) ≈ 38.
double relativeAirMass(double elevation);

/// Rayleigh optical thickness of the clean dry atmosphere per unit air mass, Kasten 1996 ("The
/// Linke turbidity factor based on improved values of the integral Rayleigh optical thickness",
/// Solar Energy 56(3):239–244), as used by the ESRA clear-sky model (Rigollier, Bauer & Wald
/// 2000, "On the clear sky model of the ESRA ... with respect to the Heliosat method", Solar
/// Energy 68(1):33–48, beam irradiance):
///   1/δ_R(m) = 6.6296 + 1.7513 m − 0.1202 m² + 0.0065 m³ − 0.00013 m⁴   (m ≤ 20)
///   1/δ_R(m) = 10.4 + 0.718 m                                            (m > 20)
double rayleighOpticalThickness(double airMass);

/// Broadband direct (beam) transmittance of the clear atmosphere, ESRA (Rigollier et al. 2000)
/// with the Linke turbidity T_L taken equal to the Preetham turbidity T (both are the
/// optical thickness of the hazy atmosphere relative to the clean dry one):
///   τ = exp(−0.8662 · T_L · m · δ_R(m)).
double sunTransmittance(double turbidity, double elevation);

/// Luminance of the true-size sun seen from sea level, kcd/m²:
///   L_sun = ExtraterrestrialSunLuminance · τ(T, h).
/// Values for T = 3: 1.41·10⁶ at the zenith, 1.13·10⁶ at h = 30°, 1.4·10⁵ at h = 0. Its ratio to
/// the Preetham zenith luminance is at least 10⁴ for T ∈ [2, 10] and h ∈ [10°, 90°] except for
/// T > 9.3 with the sun within ~4° of the zenith, where the zenith lies in the hazy aureole
/// (8.9·10³ at T = 10, h = 90°).
double physicalSunLuminance(double turbidity, double elevation);

/// The physical sun as linear Rec. 709 RGB in kcd/m², with luminance physicalSunLuminance(T, h).
/// Its colour is the extraterrestrial sun taken as white (its 5800 K is close to the D65 white
/// of the RGB space) times the spectral transmittance of Preetham et al. 1999 Appendix A.1 at
/// effective wavelengths λ = 0.61, 0.55, 0.465 µm for R, G, B:
///   t(λ) = exp(−m (0.008735 λ^−4.08 + β λ^−1.3)),  β = 0.04608 T − 0.04586  (λ in µm)
/// (Rayleigh after Leckner 1978, Ångström aerosol with α = 1.3), scaled to unit luminance. It is
/// slightly warm for a high sun ((R, G, B) ∝ (1.13, 1, 0.75) at h = 30°, T = 3) and red at the
/// horizon.
Spectrum physicalSunRadiance(double turbidity, double elevation);

/// Linear Rec. 709 (sRGB primaries, D65 white) RGB of CIE XYZ, with the matrix that inverts the
/// RGB → XYZ matrix built from the primaries (x, y) = (0.64, 0.33), (0.30, 0.60), (0.15, 0.06) and
/// D65 (0.3127, 0.3290) (as tabulated by B. Lindbloom; IEC 61966-2-1 rounds it to 4 digits):
///   R =  3.2404542 X − 1.5371385 Y − 0.4985314 Z
///   G = −0.9692660 X + 1.8760108 Y + 0.0415560 Z
///   B =  0.0556434 X − 0.2040259 Y + 1.0572252 Z
Spectrum xyzToLinearRec709(const Vec3& xyz);
/// XYZ of chromaticity (x, y) and luminance Y: X = x Y / y, Z = (1 − x − y) Y / y.
Vec3 xyYToXyz(double x, double y, double Y);

/// The clear sky of Preetham, Shirley & Smits 1999 ("A practical analytic model for daylight",
/// SIGGRAPH 99, §3.2 and Appendix A.2), for one turbidity T ∈ [2, 10] and sun direction.
///
/// Each of Y (luminance), x and y (CIE chromaticity) follows the Perez et al. 1993 ("All-weather
/// model for sky luminance distribution", Solar Energy 50(3):235–245) distribution
///   F(θ, γ) = (1 + A e^{B / cos θ}) (1 + C e^{D γ} + E cos² γ)
/// with θ the view zenith angle and γ the angle between the view and the sun, normalised at the
/// zenith (paper §3.2, "Skylight model"):
///   Y(θ, γ) = Y_z F_Y(θ, γ) / F_Y(0, θ_s),  and the same for x and y.
/// The coefficients are linear in T (Appendix A.2):
///             Y                     x                     y
///   A:   0.1787 T − 1.4630    −0.0193 T − 0.2592    −0.0167 T − 0.2608
///   B:  −0.3554 T + 0.4275    −0.0665 T + 0.0008    −0.0950 T + 0.0092
///   C:  −0.0227 T + 5.3251    −0.0004 T + 0.2125    −0.0079 T + 0.2102
///   D:   0.1206 T − 2.5771    −0.0641 T − 0.8989    −0.0441 T − 1.6537
///   E:  −0.0670 T + 0.3703    −0.0033 T + 0.0452    −0.0109 T + 0.0529
/// Zenith luminance in kcd/m² (Appendix A.2):
///   Y_z = (4.0453 T − 4.9710) tan χ − 0.2155 T + 2.4192,  χ = (4/9 − T/120)(π − 2θ_s)
/// Zenith chromaticity, θ_s in radians (Appendix A.2):
///   x_z = [T² T 1] · | 0.00166 −0.00375  0.00209  0       | · [θ_s³ θ_s² θ_s 1]ᵀ
///                    |−0.02903  0.06377 −0.03202  0.00394 |
///                    | 0.11693 −0.21196  0.06052  0.25886 |
///   y_z = [T² T 1] · | 0.00275 −0.00610  0.00317  0       | · [θ_s³ θ_s² θ_s 1]ᵀ
///                    |−0.04214  0.08970 −0.04153  0.00516 |
///                    | 0.15346 −0.26756  0.06670  0.26688 |
/// The numbers were checked against two independent transcriptions: E. Bruneton's
/// clear-sky-models (atmosphere/model/preetham/preetham.cc, 2015, typed from the paper for his
/// evaluation of clear-sky models) and several public C/C++ ports of the Utah reference code (its
/// xZC/yZC tables). All agree except that the ports have −0.03203 for the −0.03202 entry of x_z
/// (a 10⁻⁵·θ_s·T difference); the paper's −0.03202 (as in Bruneton) is used.
///
/// Near and below the horizon cos θ is clamped to at least 0.01 (the Perez form is fitted to
/// the upper hemisphere); evaluating below the horizon therefore gives the horizon value. The
/// model covers a sun at or above the horizon: a sun below it (twilight) is evaluated as if it
/// were on the horizon. xyY → XYZ → linear Rec. 709 RGB as above; negative RGB components (only
/// possible far outside the model's domain) are clamped to 0.
class PreethamSky {
  public:
    /// `sunDirection` is a unit vector (world space, z up); T must be in [2, 10] (throws
    /// shvol::Error otherwise).
    PreethamSky(double turbidity, const Vec3& sunDirection);

    /// CIE (x, y, Y) with Y in kcd/m², in the unit direction w.
    Vec3 xyY(const Vec3& w) const;
    /// Linear Rec. 709 RGB radiance in kcd/m² (luminance = Y) in the unit direction w.
    Spectrum radiance(const Vec3& w) const;

    double turbidity() const { return turbidity_; }
    /// θ_s as used by the model (≤ π/2).
    double sunZenithAngle() const { return thetaS_; }
    /// (x_z, y_z, Y_z).
    Vec3 zenithxyY() const { return {zenith_[1], zenith_[2], zenith_[0]}; }

  private:
    double turbidity_, thetaS_;
    Vec3 sun_;           ///< sun direction, lifted to the horizon if below it
    double coef_[3][5];  ///< Perez A..E for Y, x, y
    double zenith_[3];   ///< Y_z, x_z, y_z
    double norm_[3];     ///< zenith value / F(0, θ_s) for Y, x, y
};

/// Preetham sky radiance (linear Rec. 709 RGB, kcd/m²) in direction w for turbidity T and a
/// sun in direction `sun`; see PreethamSky (use that class when evaluating many directions).
Spectrum preethamSkyRadiance(const Vec3& w, const Vec3& sun, double turbidity);

struct SkyParams {
    int width = 512, height = 256;
    SkyModel model = SkyModel::Simple;
    /// Which column looks where (shvol/lights/latlong.h); row 0 is +z in both.
    LatLongMapping mapping = LatLongMapping::Blender;
    double sunElevationDegrees = 35, sunAzimuthDegrees = 60;  ///< φ from +x towards +y (world)
    double turbidity = 3;                                     ///< Preetham only, in [2, 10]
    /// Radiance inside the sun disc. Simple: the disc is (1, 0.95, 0.85)·sunRadiance (default
    /// 2000). Preetham: the disc's luminance in kcd/m² with the colour of physicalSunRadiance;
    /// default physicalSunRadiance, scaled by Ω(true radius)/Ω(r) when the radius r is not the
    /// true one, so that the sun's illuminance stays physical.
    std::optional<double> sunRadiance;
    /// Radians; unset: 0.02 (simple), TrueSunAngularRadius (preetham).
    std::optional<double> sunAngularRadius;
    /// Simple model colours.
    Spectrum zenith{0.25, 0.45, 1.0}, horizon{0.9, 0.95, 1.0}, ground{0.2, 0.18, 0.15};
    /// Preetham model: grey Lambertian ground of this albedo below the horizon.
    double groundAlbedo = 0.2;
};

/// What makeSky draws, with the defaults resolved.
struct SkySummary {
    Vec3 sunDirection;
    double sunAngularRadius;  ///< radians
    Spectrum sunRadiance;     ///< added inside the disc (simple: replaces the sky there)
    double sunLuminance;      ///< Rec. 709 luminance of sunRadiance
    double zenithLuminance;   ///< luminance of the sky at +z
    Spectrum groundRadiance;  ///< below the horizon
};
/// Resolves the defaults of `params` (validating them: throws shvol::Error on a width outside
/// [8, 16384], a non-positive sun radiance, a sun radius outside (0, 0.5], an elevation outside
/// [−90, 90], an azimuth outside [−360, 360] or a turbidity outside [2, 10]).
SkySummary describeSky(const SkyParams& params);

/// A lat-long sky of params.width × params.height pixels in params.mapping. Each pixel holds the
/// average radiance over its solid angle (θ ∈ [πy/H, π(y+1)/H), u ∈ [x/W, (x+1)/W)):
///  - the sky (smooth) is point-sampled at the pixel centre (u, v) = ((x+½)/W, (y+½)/H);
///  - pixels that the sun disc may touch (centre within r + (Δθ + Δφ)/2 of the sun) and pixels
///    that straddle the horizon are supersampled on an n×n grid that is equal-area in cos θ and
///    uniform in φ within the pixel (n ≥ 32, and large enough that the grid spacing is at most
///    r/16), so Σ L·Ω over the sun equals L_sun·2π(1 − cos r) to well under 1% (0.1% measured
///    for the true sun at widths 256 to 4096). Pixels entirely inside the disc are
///    point-sampled;
///  - a sun smaller than 1/16 of a pixel (n would exceed 256) is splatted instead: 64 × 64
///    equal-area stratified directions over the disc each add L_sun·Ω_sun/4096 to the L·Ω of
///    the pixel they fall in, which keeps the sun's energy exact however small it is.
/// Simple model: a zenith-to-horizon gradient with a soft glow around the sun, the constant
/// `ground` colour below the horizon and the disc drawn over both (shvol 0.1's sky).
/// Preetham model: PreethamSky above the horizon; below it a uniform grey Lambertian ground,
///   L_g = ρ E_h / π, with E_h the illuminance of the sky (midpoint quadrature, 64 × 128 cells in
///   (cos θ, φ)) and of the sun (L_sun Ω_sun sin h) on the horizontal plane and ρ = groundAlbedo;
///   the sun disc adds to the sky and is hidden below the horizon.
Image makeSky(const SkyParams& params);

}  // namespace shvol
