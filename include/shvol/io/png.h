#pragma once
/// \file 8-bit sRGB PNG previews of linear images (for reports and quick looks; EXR stays the
/// output format of record).
///
/// Each linear value v is scaled by 2^exposure, clamped to [0, 1] and encoded with the sRGB
/// transfer function (IEC 61966-2-1): 12.92 v for v ≤ 0.0031308, else 1.055 v^{1/2.4} − 0.055,
/// then rounded to 8 bits. The file is a standard PNG (ISO/IEC 15948): signature, IHDR (8-bit
/// RGB, no interlace), one zlib-compressed IDAT with filter type 0 per row, IEND, each chunk with
/// its CRC-32.
#include <cstdint>
#include <string>
#include <vector>

#include "shvol/core/image.h"

namespace shvol {

/// The 8-bit sRGB code of a linear value (after exposure).
uint8_t srgbByte(double linear);

/// The PNG file's bytes.
std::vector<uint8_t> encodePng(const Image& image, double exposure = 0);

/// Writes a PNG atomically (temporary file, then rename).
void writePng(const std::string& path, const Image& image, double exposure = 0);

}  // namespace shvol
