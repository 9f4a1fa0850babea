#pragma once
/// \file Warps from the unit square [0,1)² to directions.
///
/// All warps use the cylindrical (equal-area) parametrisation of DESIGN.md: z = cos θ and
/// φ = 2π u₂, so that dω = dz dφ and a uniform z gives a uniform density over solid angle
/// (Archimedes' hat-box theorem; pbrt-v4 §A.5.2 "Sampling a Unit Sphere / Hemisphere").
#include "shvol/core/math.h"

namespace shvol {

/// Uniform direction on the unit sphere: z = 1 − 2u₁, φ = 2π u₂. Density 1/(4π) per steradian.
Vec3 sampleUniformSphere(const Vec2& u);
/// Solid-angle density of sampleUniformSphere: 1/(4π).
inline double uniformSpherePdf() {
    return Inv4Pi;
}

/// Uniform direction on the hemisphere z ≥ 0 around +z: z = u₁, φ = 2π u₂. Density 1/(2π).
Vec3 sampleUniformHemisphere(const Vec2& u);
/// Solid-angle density of sampleUniformHemisphere (for z ≥ 0): 1/(2π).
inline double uniformHemispherePdf() {
    return Inv2Pi;
}

/// Cosine-weighted direction on z > 0 (Malley's method with the polar disk map):
/// r = √u₁, φ = 2π u₂, ω = (r cos φ, r sin φ, √(1 − u₁)). Density cos θ / π.
Vec3 sampleCosineHemisphere(const Vec2& u);
/// Solid-angle density of sampleCosineHemisphere: max(0, cos θ)/π.
inline double cosineHemispherePdf(double cosTheta) {
    return std::max(0.0, cosTheta) * InvPi;
}

}  // namespace shvol
