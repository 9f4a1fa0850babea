#pragma once
/// \file Procedural densities and skies for `shvol make-medium` and `shvol make-sky`.
#include <cstdint>

#include "shvol/core/image.h"
#include "shvol/core/math.h"

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

/// A sphere of radius r and density 1 with a smooth edge one voxel wide.
double sphereDensity(const Vec3& p, double radius, double edge);

struct SkyParams {
    int width = 512, height = 256;
    double sunElevationDegrees = 35, sunAzimuthDegrees = 60;  ///< φ from +x towards +y
    double sunRadiance = 2000;                                ///< inside the sun disc
    double sunAngularRadius = 0.02;                           ///< radians (the real sun: 0.0047)
    Spectrum zenith{0.25, 0.45, 1.0}, horizon{0.9, 0.95, 1.0}, ground{0.2, 0.18, 0.15};
};

/// A lat-long sky in shvol's convention (row 0 = +z, column x ↔ φ = 2π(x+½)/W): a zenith to
/// horizon gradient, a dim ground and a small bright sun.
Image makeSky(const SkyParams& params);

}  // namespace shvol
