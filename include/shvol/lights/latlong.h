#pragma once
/// \file Where each pixel of a lat-long (equirectangular) image looks, for the two conventions
/// shvol reads.
///
/// World space is z-up; θ is measured from +z and φ from +x towards +y (DESIGN.md). A W×H image
/// has row 0 at the top, looking up +z: row y ↔ θ ∈ [πy/H, π(y+1)/H). Columns differ:
///  - Blender (the default; Blender Cycles' equirectangular environment texture, and what HDRIs
///    found online are authored for): column x ↔ φ = π − 2π(x+½)/W, i.e. u = x/W runs from
///    φ = π (−x) at the left edge through +y (u = ¼) to +x at the centre (u = ½) and −y (u = ¾):
///    φ decreases to the right, as seen from inside the sphere looking out with +z up.
///    (Cycles: u = (atan2(y, x) − π)/(−2π) in kernel/camera/projection.h.)
///  - Shvol (shvol 0.1's own convention, kept as an option): column x ↔ φ = 2π(x+½)/W, φ
///    increasing to the right from +x at the left edge. It is the mirror image of the Blender
///    convention (φ ↦ π − φ); an HDRI authored for Blender renders mirrored under it.
/// Rotation: world φ = image φ + rotation (about +z) in both conventions.
#include <cmath>
#include <string>

#include "shvol/core/math.h"

namespace shvol {

enum class LatLongMapping { Blender, Shvol };

/// "blender" or "shvol"; throws shvol::Error otherwise.
LatLongMapping latLongMappingFromName(const std::string& name);
const char* latLongMappingName(LatLongMapping m);

/// Image φ (before rotation) of the horizontal image coordinate u ∈ [0, 1] (u = x/W): the map is
/// affine, φ = a + b·u with b = ∓2π.
inline double latLongPhi(LatLongMapping m, double u) {
    return m == LatLongMapping::Blender ? Pi - TwoPi * u : TwoPi * u;
}
/// u ∈ [0, 1) of an image φ (any real number; wrapped).
inline double latLongU(LatLongMapping m, double phi) {
    double u = m == LatLongMapping::Blender ? (Pi - phi) * Inv2Pi : phi * Inv2Pi;
    u -= std::floor(u);
    return u < 1 ? u : 0.0;
}
/// The direction at image coordinates (u, v) ∈ [0, 1]², v = y/H from the top, with `rotation`
/// (radians about +z) applied.
inline Vec3 latLongDirection(LatLongMapping m, double u, double v, double rotation = 0) {
    return sphericalDirection(std::cos(Pi * v), latLongPhi(m, u) + rotation);
}

}  // namespace shvol
