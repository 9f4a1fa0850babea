#include "shvol/io/procedural.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include "shvol/core/error.h"
#include "shvol/core/rng.h"

namespace shvol {

namespace {
double fade(double t) {
    return t * t * t * (t * (t * 6 - 15) + 10);
}
Vec3 gradient(int64_t i, int64_t j, int64_t k, uint64_t seed) {
    uint64_t h =
        mix64(seed ^ mix64(uint64_t(i) * 0x9E3779B1ULL ^
                           mix64(uint64_t(j) * 0x85EBCA77ULL ^ uint64_t(k) * 0xC2B2AE3DULL)));
    // A direction from two 26-bit uniforms.
    const double u = double(h & 0x3FFFFFF) / double(1 << 26), v = double(h >> 38) / double(1 << 26);
    return sphericalDirection(1 - 2 * u, TwoPi * v);
}
}  // namespace

double gradientNoise(const Vec3& p, uint64_t seed) {
    const Vec3 f = p.array().floor();
    const int64_t i = int64_t(f.x()), j = int64_t(f.y()), k = int64_t(f.z());
    const Vec3 d = p - f;
    double c[2][2][2];
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int e = 0; e < 2; ++e)
                c[a][b][e] = gradient(i + a, j + b, k + e, seed).dot(d - Vec3(a, b, e));
    const double u = fade(d.x()), v = fade(d.y()), w = fade(d.z());
    auto lerp = [](double t, double a, double b) { return a + t * (b - a); };
    // Gradient noise in 3D is bounded by √3/2; scale to about [−1, 1].
    return 2 / std::sqrt(3.0) *
           lerp(w, lerp(v, lerp(u, c[0][0][0], c[1][0][0]), lerp(u, c[0][1][0], c[1][1][0])),
                lerp(v, lerp(u, c[0][0][1], c[1][0][1]), lerp(u, c[0][1][1], c[1][1][1])));
}

double fbm(const Vec3& p, uint64_t seed, int octaves, double lacunarity, double gain) {
    double sum = 0, amp = 1, freq = 1;
    for (int o = 0; o < octaves; ++o) {
        sum += amp * gradientNoise(freq * p, seed + o);
        amp *= gain;
        freq *= lacunarity;
    }
    return sum;
}

double cloudDensity(const Vec3& p, const CloudParams& c) {
    // Flattened ellipsoid: wider than tall, with a flatter base.
    const Vec3 q(p.x() / 0.48, p.y() / 0.48, p.z() / (p.z() < 0 ? 0.28 : 0.42));
    const double r = q.norm();
    if (r >= 1) return 0;
    const double falloff = r * r * r;
    const double n = fbm(c.frequency * p, c.seed, c.octaves);
    return std::clamp((0.5 + 0.5 * n + c.coverage - falloff) * c.sharpness, 0.0, 1.0);
}

double plumeDensity(const Vec3& p, uint64_t seed) {
    const double h = p.z() + 0.5;  // height above the floor, 0 … 1
    if (h <= 0 || h >= 1) return 0;
    const double radius = 0.02 + 0.09 * h;
    // The axis drifts sideways; turbulence displaces points more the higher they are.
    const Vec3 axis(0.16 * std::sin(2.5 * h + 0.3), 0.1 * std::sin(3.7 * h), 0);
    const double swirl = 0.06 * h;
    const Vec3 q(p.x() + swirl * fbm(4 * p, seed, 3), p.y() + swirl * fbm(4 * p, seed + 1, 3), 0);
    const double d2 = (q - axis).squaredNorm() / (radius * radius);
    if (d2 >= 1) return 0;
    const double texture = std::clamp(0.6 + 0.8 * fbm(8 * p, seed + 2, 4), 0.0, 1.0);
    const double ends = std::min(1.0, std::min(h, 1 - h) / 0.05);  // fades at floor and top
    return (1 - d2) * texture * ends;
}

double sphereDensity(const Vec3& p, double radius, double edge) {
    const double d = p.norm() - radius;
    return std::clamp(0.5 - d / std::max(edge, 1e-12), 0.0, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Skies. Equations and sources are in the header.

SkyModel skyModelFromName(const std::string& name) {
    if (name == "simple") return SkyModel::Simple;
    if (name == "preetham") return SkyModel::Preetham;
    throw Error("unknown sky model \"" + name + "\"; expected \"simple\" or \"preetham\"");
}

const char* skyModelName(SkyModel m) {
    return m == SkyModel::Simple ? "simple" : "preetham";
}

double relativeAirMass(double elevation) {
    const double h = std::max(elevation, 0.0);
    const double hDeg = h * 180 / Pi;
    return 1 / (std::sin(h) + 0.50572 * std::pow(hDeg + 6.07995, -1.6364));
}

double rayleighOpticalThickness(double m) {
    if (m <= 20) return 1 / (6.6296 + m * (1.7513 + m * (-0.1202 + m * (0.0065 - m * 0.00013))));
    return 1 / (10.4 + 0.718 * m);
}

double sunTransmittance(double turbidity, double elevation) {
    const double m = relativeAirMass(elevation);
    return std::exp(-0.8662 * turbidity * m * rayleighOpticalThickness(m));
}

double physicalSunLuminance(double turbidity, double elevation) {
    return ExtraterrestrialSunLuminance * sunTransmittance(turbidity, elevation);
}

namespace {
double rec709Luminance(const Spectrum& s) {
    return 0.2126 * s[0] + 0.7152 * s[1] + 0.0722 * s[2];
}
}  // namespace

Spectrum physicalSunRadiance(double turbidity, double elevation) {
    const double m = relativeAirMass(elevation);
    const double beta = 0.04608 * turbidity - 0.04586;
    const double lambda[3] = {0.61, 0.55, 0.465};  // µm, effective R, G, B
    Spectrum t;
    for (int k = 0; k < 3; ++k) {
        const double tau = 0.008735 * std::pow(lambda[k], -4.08) + beta * std::pow(lambda[k], -1.3);
        t[k] = std::exp(-m * tau);
    }
    return t * (physicalSunLuminance(turbidity, elevation) / rec709Luminance(t));
}

Vec3 xyYToXyz(double x, double y, double Y) {
    return {x * Y / y, Y, (1 - x - y) * Y / y};
}

Spectrum xyzToLinearRec709(const Vec3& c) {
    return {3.2404542 * c[0] - 1.5371385 * c[1] - 0.4985314 * c[2],
            -0.9692660 * c[0] + 1.8760108 * c[1] + 0.0415560 * c[2],
            0.0556434 * c[0] - 0.2040259 * c[1] + 1.0572252 * c[2]};
}

namespace {
// Perez et al. 1993 F(θ, γ) with coefficients c = (A, B, C, D, E); cos θ already clamped.
double perez(const double c[5], double cosTheta, double gamma) {
    const double cosGamma = std::cos(gamma);
    return (1 + c[0] * std::exp(c[1] / cosTheta)) *
           (1 + c[2] * std::exp(c[3] * gamma) + c[4] * cosGamma * cosGamma);
}
constexpr double MinCosTheta = 0.01;
}  // namespace

PreethamSky::PreethamSky(double T, const Vec3& sunDirection) : turbidity_(T) {
    if (!(T >= 2 && T <= 10))
        throw Error("Preetham sky: turbidity " + std::to_string(T) + " is outside [2, 10]");
    sun_ = sunDirection.normalized();
    if (sun_.z() < 0) {  // twilight is outside the model: use the sun on the horizon
        const Vec3 h(sun_.x(), sun_.y(), 0);
        sun_ = h.norm() > 1e-12 ? Vec3(h.normalized()) : Vec3(1, 0, 0);
    }
    thetaS_ = safeAcos(sun_.z());
    // Appendix A.2: Perez coefficients (A, B, C, D, E) = slope·T + intercept, for Y, x, y.
    static const double slope[3][5] = {{0.1787, -0.3554, -0.0227, 0.1206, -0.0670},
                                       {-0.0193, -0.0665, -0.0004, -0.0641, -0.0033},
                                       {-0.0167, -0.0950, -0.0079, -0.0441, -0.0109}};
    static const double intercept[3][5] = {{-1.4630, 0.4275, 5.3251, -2.5771, 0.3703},
                                           {-0.2592, 0.0008, 0.2125, -0.8989, 0.0452},
                                           {-0.2608, 0.0092, 0.2102, -1.6537, 0.0529}};
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 5; ++i) coef_[k][i] = slope[k][i] * T + intercept[k][i];
    // Zenith luminance (kcd/m²) and chromaticity.
    const double chi = (4.0 / 9.0 - T / 120.0) * (Pi - 2 * thetaS_);
    zenith_[0] = (4.0453 * T - 4.9710) * std::tan(chi) - 0.2155 * T + 2.4192;
    static const double mx[3][4] = {{0.00166, -0.00375, 0.00209, 0},
                                    {-0.02903, 0.06377, -0.03202, 0.00394},
                                    {0.11693, -0.21196, 0.06052, 0.25886}};
    static const double my[3][4] = {{0.00275, -0.00610, 0.00317, 0},
                                    {-0.04214, 0.08970, -0.04153, 0.00516},
                                    {0.15346, -0.26756, 0.06670, 0.26688}};
    const double th[4] = {thetaS_ * thetaS_ * thetaS_, thetaS_ * thetaS_, thetaS_, 1};
    const double tt[3] = {T * T, T, 1};
    zenith_[1] = zenith_[2] = 0;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) {
            zenith_[1] += tt[r] * mx[r][c] * th[c];
            zenith_[2] += tt[r] * my[r][c] * th[c];
        }
    for (int k = 0; k < 3; ++k) norm_[k] = zenith_[k] / perez(coef_[k], 1.0, thetaS_);
}

Vec3 PreethamSky::xyY(const Vec3& w) const {
    const double cosTheta = std::max(w.z(), MinCosTheta);
    const double gamma = safeAcos(w.dot(sun_));
    const double Y = norm_[0] * perez(coef_[0], cosTheta, gamma);
    const double x = norm_[1] * perez(coef_[1], cosTheta, gamma);
    const double y = norm_[2] * perez(coef_[2], cosTheta, gamma);
    return {x, y, Y};
}

Spectrum PreethamSky::radiance(const Vec3& w) const {
    const Vec3 c = xyY(w);
    return xyzToLinearRec709(xyYToXyz(c[0], c[1], c[2])).max(0.0);
}

Spectrum preethamSkyRadiance(const Vec3& w, const Vec3& sun, double turbidity) {
    return PreethamSky(turbidity, sun).radiance(w);
}

double capProjectedSolidAngleAboveHorizon(double r, double e) {
    const double sinR = std::sin(r), cosT = std::sin(e), sinT = std::cos(e);
    if (cosT >= sinR) return Pi * sinR * sinR * cosT;
    if (cosT <= -sinR) return 0;
    // |cos θ| < sin r < 1, so sin θ > 0 and |y| < 1.
    const double x = std::cos(r) / sinR, y = std::clamp(-x * cosT / sinT, -1.0, 1.0);
    const double sinTRootY = sinT * std::sqrt(1 - y * y);
    return std::max(0.0,
                    sinR * sinR * (cosT * std::acos(y) - x * sinTRootY) + std::atan(sinTRootY / x));
}

namespace {
std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

Vec3 sunDirectionOf(const SkyParams& s) {
    const double el = s.sunElevationDegrees * Pi / 180, az = s.sunAzimuthDegrees * Pi / 180;
    return sphericalDirection(std::sin(el), az);
}

// Horizontal illuminance of the Preetham sky: midpoint rule on 64 × 128 cells of (cos θ, φ).
Spectrum skyIlluminance(const PreethamSky& sky) {
    const int nz = 64, nphi = 128;
    Spectrum E = Spectrum::Zero();
    for (int i = 0; i < nz; ++i) {
        const double z = (i + 0.5) / nz;
        for (int j = 0; j < nphi; ++j)
            E += sky.radiance(sphericalDirection(z, TwoPi * (j + 0.5) / nphi)) * z;
    }
    return E * (1.0 / nz) * (TwoPi / nphi);
}
}  // namespace

SkySummary describeSky(const SkyParams& s) {
    if (s.width < 8 || s.width > 16384)
        throw Error("sky: width " + std::to_string(s.width) + " is outside [8, 16384]");
    if (s.height < 1) throw Error("sky: height " + std::to_string(s.height) + " is below 1");
    if (!(s.sunElevationDegrees >= -90 && s.sunElevationDegrees <= 90))
        throw Error("sky: sun elevation " + num(s.sunElevationDegrees) + "° is outside [-90, 90]");
    if (!(s.sunAzimuthDegrees >= -360 && s.sunAzimuthDegrees <= 360))
        throw Error("sky: sun azimuth " + num(s.sunAzimuthDegrees) + "° is outside [-360, 360]");
    if (s.sunRadiance && !(*s.sunRadiance > 0 && std::isfinite(*s.sunRadiance)))
        throw Error("sky: sun radiance " + num(*s.sunRadiance) + " must be positive");
    if (s.sunAngularRadius && !(*s.sunAngularRadius > 0 && *s.sunAngularRadius <= 0.5))
        throw Error("sky: sun radius " + num(*s.sunAngularRadius) + " rad is outside (0, 0.5]");
    if (!(s.turbidity >= 2 && s.turbidity <= 10))
        throw Error("sky: turbidity " + num(s.turbidity) + " is outside [2, 10]");
    if (!(s.groundAlbedo >= 0 && s.groundAlbedo <= 1))
        throw Error("sky: ground albedo " + num(s.groundAlbedo) + " is outside [0, 1]");

    SkySummary out;
    out.sunDirection = sunDirectionOf(s);
    const double elevation = s.sunElevationDegrees * Pi / 180;
    if (s.model == SkyModel::Simple) {
        out.sunAngularRadius = s.sunAngularRadius.value_or(0.02);
        out.sunRadiance = Spectrum(1.0, 0.95, 0.85) * s.sunRadiance.value_or(2000);
        // The gradient is s.zenith at +z, plus the glow around the sun.
        out.zenithLuminance =
            rec709Luminance(s.zenith + Spectrum(1.0, 0.9, 0.7) * 0.8 *
                                           std::pow(std::max(0.0, out.sunDirection.z()), 32));
        out.groundRadiance = s.ground;
    } else {
        out.sunAngularRadius = s.sunAngularRadius.value_or(TrueSunAngularRadius);
        const Spectrum phys = physicalSunRadiance(s.turbidity, elevation);
        if (s.sunRadiance)
            out.sunRadiance = phys * (*s.sunRadiance / rec709Luminance(phys));
        else  // keep the sun's illuminance when the disc is not the true size: L π sin² r (the
              // radiance times the solid angle, kept until 7 Dec, lost (1 − cos r)/2 of it, 6.1%
              // at r = 0.5; helper 130)
            out.sunRadiance = phys * (capProjectedSolidAngle(TrueSunAngularRadius) /
                                      capProjectedSolidAngle(out.sunAngularRadius));
        const PreethamSky sky(s.turbidity, out.sunDirection);
        out.zenithLuminance = sky.xyY(Vec3(0, 0, 1))[2];
        // The disc's part above the horizon, as the image shows it (a point sun at the disc's
        // centre gave 6.5% more for a high disc of 0.5 rad, 13.6% less at 10° and nothing below
        // 0°).
        const Spectrum sunE =
            out.sunRadiance * capProjectedSolidAngleAboveHorizon(out.sunAngularRadius, elevation);
        out.groundRadiance = (skyIlluminance(sky) + sunE) * (s.groundAlbedo * InvPi);
    }
    out.sunLuminance = rec709Luminance(out.sunRadiance);
    // Radiances stay at most 1e30, as the scene's (float32 ends at 3.4e38, and the sky's sums
    // must not reach it either).
    if (!(out.sunRadiance.maxCoeff() <= 1e30)) {
        const std::string radiance = num(out.sunRadiance.maxCoeff());
        if (s.sunRadiance)
            failOption("--sun-radiance", "gives the sun disc a radiance of " + radiance +
                                             " (largest channel), above the limit of 1e30");
        failOption(
            "--sun-radius",
            "a sun of radius " + num(out.sunAngularRadius) + " rad would need a radiance of " +
                radiance +
                " for the physical illuminance, above the limit of 1e30; give a larger radius");
    }
    return out;
}

Image makeSky(const SkyParams& s) {
    const SkySummary sum = describeSky(s);
    const Vec3 sun = sum.sunDirection;
    const double r = sum.sunAngularRadius, cosSun = std::cos(r);
    const bool simple = s.model == SkyModel::Simple;
    std::optional<PreethamSky> sky;
    if (!simple) sky.emplace(s.turbidity, sun);

    const int W = s.width, H = s.height;
    const double dTheta = Pi / H, dPhi = TwoPi / W;
    // Sub-samples per pixel side for pixels on the sun's edge: spacing at most r/16. A sun
    // smaller than 1/16 of a pixel is splatted instead (below).
    const double nWanted = std::ceil(16 * std::max(dTheta, dPhi) / r);
    const bool splatSun = nWanted > 256;
    const int nSun = splatSun ? 0 : std::max(32, int(nWanted));

    // Radiance without the sun: sky above the horizon, ground below.
    auto background = [&](const Vec3& w) -> Spectrum {
        if (simple) {
            if (w.z() < 0) return s.ground;
            const double t = std::pow(1 - w.z(), 3);
            Spectrum L = s.zenith * (1 - t) + s.horizon * t;
            // A soft glow around the sun.
            L += Spectrum(1.0, 0.9, 0.7) * 0.8 * std::pow(std::max(0.0, w.dot(sun)), 32);
            return L;
        }
        return w.z() >= 0 ? sky->radiance(w) : sum.groundRadiance;
    };
    // With the sun disc: the simple model draws it over sky and ground, the Preetham sun adds to
    // the sky (the sky in front of it) and is hidden by the ground.
    auto radianceAt = [&](const Vec3& w) -> Spectrum {
        const Spectrum L = background(w);
        if (splatSun || w.dot(sun) < cosSun) return L;
        if (simple) return sum.sunRadiance;
        return w.z() >= 0 ? Spectrum(L + sum.sunRadiance) : L;
    };

    // Every direction of a pixel lies within (Δθ + Δφ)/2 of its centre: Δθ/2 along the meridian,
    // then at most sin θ·Δφ/2 along the parallel, which is longer than the great-circle arc.
    const double pixelRadius = 0.5 * (dTheta + dPhi);
    const double cosTouch = std::cos(std::min(r + pixelRadius + 1e-9, Pi));
    const double inner = r - pixelRadius - 1e-9;
    const double cosInside = inner > 0 ? std::cos(inner) : 2.0;  // 2: never entirely inside
    const int nHorizon = 8;

    // The disc's part of pixel (x, y) on its edge, exact in θ: along each of n meridians φ of the
    // pixel the disc covers the θ where the angular distance to the sun is at most r, an interval
    // [α − β, α + β] about the sun's projection α onto the meridian's plane, from the right
    // spherical triangle of hypotenuse r and legs δ (the sun's distance from that plane) and β:
    // cos r = cos δ cos β, so sin²(β/2) = (sin²(r/2) − sin²(δ/2)) / cos δ (no cancellation for a
    // small sun). Its ∫ sin θ dθ within the row (above the horizon for the Preetham sun, which the
    // ground hides), over the row's, is the meridian's share. A regular grid in θ put the disc's
    // edge at the same sample in every pixel of a polar row: a sun at the zenith lost 5.8% of its
    // energy at width 700 (helper 72).
    const double sinHalfR = std::sin(0.5 * r);
    auto discShare = [&](int x, int y, int n) {
        const double t0 = y * dTheta, t1 = std::min((y + 1) * dTheta, simple ? Pi : 0.5 * Pi);
        const double row = 2 * std::sin((y + 0.5) * dTheta) * std::sin(0.5 * dTheta);  // ∫ sin θ
        double acc = 0;
        for (int i = 0; i < n && t1 > t0; ++i) {
            const double phi = latLongPhi(s.mapping, (x + (i + 0.5) / n) / W);
            const double cp = std::cos(phi), sp = std::sin(phi);
            const double sinDelta = std::min(1.0, std::abs(sun.y() * cp - sun.x() * sp));
            const double sinHalfDelta = std::sin(0.5 * std::asin(sinDelta));
            if (!(sinHalfDelta < sinHalfR)) continue;
            const double beta =
                2 * std::asin(std::min(
                        1.0, std::sqrt((sinHalfR - sinHalfDelta) * (sinHalfR + sinHalfDelta) /
                                       safeSqrt(1 - sinDelta * sinDelta))));
            const double alpha = std::atan2(sun.x() * cp + sun.y() * sp, sun.z());
            for (const double turn : {-TwoPi, 0.0, TwoPi}) {  // (an interval across a pole)
                const double lo = std::max(t0, alpha - beta + turn),
                             hi = std::min(t1, alpha + beta + turn);
                if (!(hi > lo)) continue;
                acc += 2 * std::sin(0.5 * (lo + hi)) * std::sin(0.5 * (hi - lo)) / row;
            }
        }
        return acc / n;
    };

    Image img(W, H);
    for (int y = 0; y < H; ++y) {
        const double z0 = std::cos(y * dTheta), z1 = std::cos((y + 1) * dTheta);
        const bool straddlesHorizon = z0 > 0 && z1 < 0;
        // The mean over the pixel of `radiance` on an n×n grid uniform in θ and in u, each row
        // weighted by sin θ (dω = sin θ dθ dφ). Rows equal-area in cos θ were up to 3× coarser
        // than Δθ/n in angle in the rows at the poles (dz ≈ θ dθ there): a sun at the zenith held
        // +32% of its energy at width 128 (helper 68).
        // With `underDisc`, also the mean of `radiance` over the samples inside the sun's disc
        // (unchanged where none is).
        auto average = [&](int x, int n, const auto& radiance, Spectrum* underDisc = nullptr) {
            Spectrum acc = Spectrum::Zero(), inside = Spectrum::Zero();
            double weights = 0, insideWeights = 0;
            for (int j = 0; j < n; ++j) {
                const double theta = (y + (j + 0.5) / n) * dTheta, w = std::sin(theta);
                for (int i = 0; i < n; ++i) {
                    const double phi = latLongPhi(s.mapping, (x + (i + 0.5) / n) / W);
                    const Vec3 d = sphericalDirection(std::cos(theta), phi);
                    const Spectrum L = radiance(d);
                    acc += w * L, weights += w;
                    if (underDisc && d.dot(sun) >= cosSun) inside += w * L, insideWeights += w;
                }
            }
            if (insideWeights > 0) *underDisc = inside / insideWeights;
            return Spectrum(acc / weights);
        };
        for (int x = 0; x < W; ++x) {
            const Vec3 w = latLongDirection(s.mapping, (x + 0.5) / W, (y + 0.5) / H);
            const double c = w.dot(sun);
            Spectrum L;
            if (!splatSun && c >= cosTouch && c < cosInside) {
                // The simple sun replaces the sky: less the sky under it, the pixel's own grid's
                // mean there, so that a pixel the disc covers is the sun's radiance (the sky at
                // each covered interval's middle left 0.9% of it in such a pixel; helper 75).
                Spectrum under = background(w);
                const double f = discShare(x, y, 16 * nSun);
                L = average(x, nSun, background, simple ? &under : nullptr) +
                    f * (simple ? Spectrum(sum.sunRadiance - under) : sum.sunRadiance);
            } else if (straddlesHorizon)
                L = average(x, nHorizon, radianceAt);
            else
                L = radianceAt(w);
            img.set(x, y, L);
        }
    }

    if (splatSun) {
        // A sun much smaller than a pixel: 64 × 64 stratified directions, equal-area over the
        // disc (uniform in 1 − cos α and in the angle around the sun), each carrying Ω_sun/N of
        // the sun's L·Ω into the pixel it falls in (divided by that pixel's solid angle). The
        // simple model's sun replaces the background, so that is taken out again.
        const int nA = 64, nB = 64;
        const double weight = capSolidAngle(r) / (nA * nB);
        // Summed in double per pixel, then added once: added to the float image sample by sample,
        // a small sun's increments rounded away against the sky (a sun of radius 10⁻⁵ vanished
        // at width 512; helper 72).
        std::map<size_t, Spectrum> splat;
        const double oneMinusCosR = 2 * sqr(std::sin(0.5 * r));  // 1 − cos r without cancellation
        const Frame frame(sun);
        for (int a = 0; a < nA; ++a) {
            const double oneMinusCos = oneMinusCosR * (a + 0.5) / nA;
            const double cosA = 1 - oneMinusCos, sinA = safeSqrt(oneMinusCos * (2 - oneMinusCos));
            for (int b = 0; b < nB; ++b) {
                const double beta = TwoPi * (b + 0.5) / nB;
                const Vec3 w =
                    frame.toWorld(Vec3(sinA * std::cos(beta), sinA * std::sin(beta), cosA))
                        .normalized();
                if (!simple && w.z() < 0) continue;
                const int y = std::clamp(int(safeAcos(w.z()) / dTheta), 0, H - 1);
                const int x =
                    std::clamp(int(latLongU(s.mapping, std::atan2(w.y(), w.x())) * W), 0, W - 1);
                const double omega = (std::cos(y * dTheta) - std::cos((y + 1) * dTheta)) * dPhi;
                const Spectrum add =
                    simple ? Spectrum(sum.sunRadiance - background(w)) : sum.sunRadiance;
                splat.try_emplace(size_t(y) * W + x, Spectrum::Zero()).first->second +=
                    add * (weight / omega);
            }
        }
        for (const auto& [pixel, add] : splat) {
            const int x = int(pixel % W), y = int(pixel / W);
            img.set(x, y, Spectrum(img.at(x, y) + add));
        }
    }
    return img;
}

}  // namespace shvol
