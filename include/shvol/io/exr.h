#pragma once
/// \file OpenEXR images: float32 RGB, linear.
#include <string>

#include "shvol/core/image.h"

namespace shvol {

/// The pixel values readExr accepts besides finite non-negative ones.
enum class ExrValues {
    Radiance,   ///< none: a sky, a reference, a run's image
    Preview,    ///< +inf too: a render writes it for a mean beyond the float range, and
                ///< --variance for an unknown standard error
    Compared,   ///< any but NaN: ±inf, and negative values (another renderer's filter can ring
                ///< below 0)
    Reference,  ///< finite, negative too: a batch's given reference, against which an infinite
                ///< value would make every run's error infinite
};

/// Reads the R, G, B channels (or a single Y channel, replicated) of an EXR file as floats.
/// Errors (missing or corrupt file, no colour channels, NaN, and infinite or negative values
/// that `values` does not accept) name the file and the pixel.
Image readExr(const std::string& path, ExrValues values = ExrValues::Radiance);

/// Why the file at path is not a whole OpenEXR image, read from its header and chunk table alone
/// (cheap: no pixel is decoded): "not a readable OpenEXR file (…)", "its pixel data is cut
/// short"; empty when it is whole. Its values are not checked (readExr does that).
std::string exrDamage(const std::string& path);

/// Writes float32 R, G, B atomically (temporary file, then rename).
void writeExr(const std::string& path, const Image& image);
/// Writes float32 R, G, B into `tmp` itself, a temporary of writeAtomically for `path`, which
/// errors name.
void writeExrTo(const std::string& tmp, const Image& image, const std::string& path);

}  // namespace shvol
