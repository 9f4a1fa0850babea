#pragma once
/// \file OpenEXR images: float32 RGB, linear.
#include <string>

#include "shvol/core/image.h"

namespace shvol {

/// Reads the R, G, B channels (or a single Y channel, replicated) of an EXR file as floats.
/// Errors (missing or corrupt file, no colour channels, NaN/Inf or negative pixels) name the file
/// and the pixel. \param allowInfinity accept +inf (a render writes it for a mean beyond the
/// float range, and --variance for an unknown standard error): for previews.
Image readExr(const std::string& path, bool allowInfinity = false);

/// Writes float32 R, G, B atomically (temporary file, then rename).
void writeExr(const std::string& path, const Image& image);

}  // namespace shvol
