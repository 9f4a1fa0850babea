#pragma once
/// \file Vectors, spectra and orthonormal frames.
///
/// Directions follow DESIGN.md: θ is measured from +z, φ from +x towards +y, so
///   ω(θ, φ) = (sin θ cos φ, sin θ sin φ, cos θ).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace shvol {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
/// Linear RGB radiance or throughput.
using Spectrum = Eigen::Array3d;

inline constexpr double Pi = 3.14159265358979323846;
inline constexpr double TwoPi = 2.0 * Pi;
inline constexpr double FourPi = 4.0 * Pi;
inline constexpr double InvPi = 1.0 / Pi;
inline constexpr double Inv2Pi = 1.0 / TwoPi;
inline constexpr double Inv4Pi = 1.0 / FourPi;

template <typename T>
inline T sqr(T x) {
    return x * x;
}
/// The least float ≥ v and the greatest float ≤ v: v rounded outward, for bounds kept in float
/// (MajorantGrid); exact for a v that is a float.
inline float floatAtLeast(double v) {
    const float f = float(v);
    return double(f) < v ? std::nextafter(f, INFINITY) : f;
}
inline float floatAtMost(double v) {
    const float f = float(v);
    return double(f) > v ? std::nextafter(f, -INFINITY) : f;
}
/// ⌊x⌋ for finite |x| < 2³¹ (callers keep their arguments in that range: points inside a
/// majorant grid or its bricks): a truncation and a correction (std::floor is a libm call unless
/// the target has SSE4.1).
inline int floorToInt(double x) {
    const int i = int(x);
    return i - (double(i) > x);
}

/// The Exp(1) variate −ln(1 − u) of u ∈ [0, 1). For u a multiple of 2⁻⁵³ (Rng::uniform and
/// SobolSampler give such numbers) 1 − u is exact, so log is as accurate as log1p(−u) here, and
/// glibc's log is about 1.8× faster than its log1p.
inline double exponentialVariate(double u) {
    return -std::log(1 - u);
}

/// The Šidák threshold of one test of a family of numTests ≥ 1 at level alpha: a test passes when
/// its p-value exceeds 1 − (1 − alpha)^(1/numTests) (the χ² tests, batch's z-test).
inline double sidakThreshold(double alpha, double numTests) {
    return 1.0 - std::pow(1.0 - alpha, 1.0 / numTests);
}

/// u clamped into [0, 1) for a sampler: NaN and negative values to 0, values ≥ 1 to the largest
/// double below 1 (so that ⌊u n⌋ < n and no NaN reaches an index).
inline double clampToUnit(double u) {
    return u >= 0 ? std::min(u, 0x1.fffffffffffffp-1) : 0.0;
}

/// √max(0, x): guards square roots of quantities that are ≥ 0 analytically but not in rounding.
inline double safeSqrt(double x) {
    return std::sqrt(std::max(0.0, x));
}
inline double safeAcos(double x) {
    return std::acos(std::clamp(x, -1.0, 1.0));
}

/// (cos φ, sin φ) from one call (glibc's sincos: the same values as std::cos and std::sin, for
/// about the price of one of them).
inline Vec2 cosSin(double phi) {
    double s, c;
    ::sincos(phi, &s, &c);
    return {c, s};
}

/// (cos 2πu, sin 2πu), for the azimuth φ = 2πu of a sampler's u ∈ [0, 1] (any finite |u| < 2²⁸
/// works): u is reduced to the nearest quarter turn k/4 (r = 4u − k ∈ [−½, ½] is exact for the
/// samplers' multiples of 2⁻⁵³, and within an ulp for any u), and sin x, cos x at x = (π/2)·r,
/// |x| ≤ π/4, are their Taylor polynomials through x¹⁵ and x¹⁶ (the first term left out is below
/// 10⁻¹⁶ of the result there), turned by k quarter turns by swapping and negating. Within
/// 3·10⁻¹⁶ of the exact values (tested against long double; sincos(2π·u), whose argument is
/// already rounded, is off by up to 7·10⁻¹⁶), and 2.7× as fast as it (build/bench_phase,
/// Azimuth; a uniform number included).
inline Vec2 cosSin2Pi(double u) {
    const double q = 4 * u;
    const int k = floorToInt(q + 0.5);
    const double x = (q - k) * (Pi / 2), x2 = x * x;
    // ±1/n!: sin x = x (1 + Σ kSin[i] x^(2i+2)), cos x = 1 + Σ kCos[i] x^(2i+2).
    constexpr double kSin[] = {-1.0 / 6,        1.0 / 120,        -1.0 / 5040,         1.0 / 362880,
                               -1.0 / 39916800, 1.0 / 6227020800, -1.0 / 1307674368000};
    constexpr double kCos[] = {
        -1.0 / 2,       1.0 / 24,        -1.0 / 720,         1.0 / 40320,
        -1.0 / 3628800, 1.0 / 479001600, -1.0 / 87178291200, 1.0 / 20922789888000};
    double s = 0, c = 0;  // Horner from the highest power
    for (int i = 6; i >= 0; --i) s = x2 * (kSin[i] + s);
    for (int i = 7; i >= 0; --i) c = x2 * (kCos[i] + c);
    const double cs[2] = {1 + c, x * (1 + s)};  // cos x, sin x
    // cos and sin of x + kπ/2: (c, s), (−s, c), (−c, −s), (s, −c) for k mod 4 = 0 … 3, without a
    // branch (k is random: a branch would be mispredicted half of the time).
    const int odd = k & 1;
    return {double(1 - ((k + 1) & 2)) * cs[odd], double(1 - (k & 2)) * cs[odd ^ 1]};
}

/// The cosine μ of an angle with 1 − μ and 1 + μ, each to the relative accuracy of its own size.
/// Near μ = ±1, where μ itself rounds the angle away (1 − μ of an angle of 10⁻⁶ rad is 5·10⁻¹³,
/// while μ is resolved to 1.1·10⁻¹⁶), a lobe of width (1 − g)² as in Henyey–Greenstein with
/// g → ±1 must be evaluated from the complements. For unit vectors a, b: 1 − μ = ½|a − b|² and
/// 1 + μ = ½|a + b|².
struct AngleCosine {
    double mu, oneMinusMu, onePlusMu;
    /// From μ alone, clamped to [−1, 1] (the complements as accurate as μ).
    static AngleCosine of(double mu) {
        mu = std::clamp(mu, -1.0, 1.0);
        return {mu, 1 - mu, 1 + mu};
    }
    /// Of the angle θ ∈ [0, π] itself: 1 − μ = 2 sin²(θ/2), 1 + μ = 2 cos²(θ/2) (the
    /// quadrature nodes of fitZonal).
    static AngleCosine ofAngle(double theta) {
        const double s = std::sin(0.5 * theta), c = std::cos(0.5 * theta);
        return {std::cos(theta), 2 * s * s, 2 * c * c};
    }
    /// Of the unit vectors a and b.
    static AngleCosine between(const Vec3& a, const Vec3& b) {
        return {std::clamp(a.dot(b), -1.0, 1.0), std::min(2.0, 0.5 * (a - b).squaredNorm()),
                std::min(2.0, 0.5 * (a + b).squaredNorm())};
    }
    /// sin θ = √((1 − μ)(1 + μ)).
    double sinTheta() const { return safeSqrt(oneMinusMu * onePlusMu); }
};

/// ω(θ, φ) from cos θ, sin θ and (cos φ, sin φ).
inline Vec3 sphericalDirectionFromCosSin(double cosTheta, double sinTheta, const Vec2& cosSinPhi) {
    return {sinTheta * cosSinPhi.x(), sinTheta * cosSinPhi.y(), cosTheta};
}
/// ω(θ, φ) from cos θ and (cos φ, sin φ), with sin θ = √(1 − cos²θ).
inline Vec3 sphericalDirectionFromCosSin(double cosTheta, const Vec2& cosSinPhi) {
    return sphericalDirectionFromCosSin(cosTheta, safeSqrt(1.0 - cosTheta * cosTheta), cosSinPhi);
}
/// ω(cos θ, φ).
inline Vec3 sphericalDirection(double cosTheta, double phi) {
    return sphericalDirectionFromCosSin(cosTheta, cosSin(phi));
}
/// ω(cos θ, 2πu): sphericalDirection with the azimuth of a sampler's u (cosSin2Pi).
inline Vec3 sphericalDirection2Pi(double cosTheta, double u) {
    return sphericalDirectionFromCosSin(cosTheta, cosSin2Pi(u));
}
/// ω(θ, 2πu) with sin θ from the complements of cos θ (AngleCosine): accurate near the poles.
inline Vec3 sphericalDirection2Pi(const AngleCosine& c, double u) {
    return sphericalDirectionFromCosSin(c.mu, c.sinTheta(), cosSin2Pi(u));
}
/// φ ∈ [0, 2π) of a direction.
inline double sphericalPhi(const Vec3& w) {
    const double p = std::atan2(w.y(), w.x());
    return p < 0 ? p + TwoPi : p;
}

/// Orthonormal frame (s, t, n): world ↔ local, with local +z = n.
/// Built with the branchless construction of Duff et al. 2017, "Building an Orthonormal
/// Basis, Revisited" (JCGT 6(1)).
struct Frame {
    Vec3 s, t, n;
    Frame() : s(1, 0, 0), t(0, 1, 0), n(0, 0, 1) {}
    explicit Frame(const Vec3& normal) : n(normal) {
        const double sign = std::copysign(1.0, n.z());
        const double a = -1.0 / (sign + n.z());
        const double b = n.x() * n.y() * a;
        s = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
        t = Vec3(b, sign + n.y() * n.y() * a, -n.y());
    }
    /// The frame whose x axis is `tangent` projected onto the plane ⟂ normal (s = normalised
    /// tangent − n (n·tangent), t = n × s): a surface's own axes, continuous wherever its tangent
    /// is. Where the tangent is (nearly) parallel to the normal, `second` takes its place (a
    /// surface's y axis, on a box's faces ⟂ its x axis), and where that is too, Frame(normal).
    Frame(const Vec3& normal, const Vec3& tangent, const Vec3& second = Vec3::Zero())
        : Frame(normal) {
        Vec3 p = tangent - normal * normal.dot(tangent);
        if (!(p.squaredNorm() > 1e-12 * tangent.squaredNorm()))
            p = second - normal * normal.dot(second);
        if (!(p.squaredNorm() > 1e-12 * std::max(tangent.squaredNorm(), second.squaredNorm())))
            return;
        p -= normal * normal.dot(p);  // (again: a tangent near the normal leaves p·n ~ 10⁻¹⁰)
        s = p.normalized();
        t = n.cross(s);
    }
    Vec3 toLocal(const Vec3& v) const { return {v.dot(s), v.dot(t), v.dot(n)}; }
    Vec3 toWorld(const Vec3& v) const { return s * v.x() + t * v.y() + n * v.z(); }
};

/// Luminance-like scalar of a spectrum used for Russian roulette.
inline double maxComponent(const Spectrum& s) {
    return s.maxCoeff();
}
/// Rec. 709 luminance 0.2126 R + 0.7152 G + 0.0722 B, clamped at 0 (importance of a radiance).
inline double luminance(const Spectrum& s) {
    return std::max(0.0, 0.2126 * s[0] + 0.7152 * s[1] + 0.0722 * s[2]);
}
inline bool isFinite(const Spectrum& s) {
    return s.allFinite();
}

}  // namespace shvol
