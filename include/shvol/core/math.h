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

/// ω(cos θ, φ) with sin θ = √(1 − cos²θ).
inline Vec3 sphericalDirection(double cosTheta, double phi) {
    const double sinTheta = safeSqrt(1.0 - cosTheta * cosTheta);
    const Vec2 cs = cosSin(phi);
    return {sinTheta * cs.x(), sinTheta * cs.y(), cosTheta};
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
