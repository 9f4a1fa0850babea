#pragma once
/// \file 8-bit sRGB PNG previews of linear images (for reports and quick looks; EXR stays the
/// output format of record).
///
/// Each linear value v is scaled by 2^exposure, clamped to [0, 1] and encoded with the sRGB
/// transfer function (IEC 61966-2-1): 12.92 v for v ≤ 0.0031308, else 1.055 v^{1/2.4} − 0.055,
/// then rounded to 8 bits. The file is a standard PNG (ISO/IEC 15948): signature, IHDR (8-bit
/// RGB, no interlace), the zlib-compressed rows (filter type 0 each) in IDAT chunks of at most
/// kMaxPngIdat bytes, IEND, each chunk with its CRC-32.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "shvol/core/image.h"

namespace shvol {

/// The 8-bit sRGB code of a linear value (after exposure).
uint8_t srgbByte(double linear);

/// Largest IDAT chunk written: 2^30 bytes, below PNG's 2^31 − 1.
constexpr size_t kMaxPngIdat = size_t(1) << 30;

/// The PNG file's bytes, its compressed data cut into IDAT chunks of at most maxIdat bytes.
std::vector<uint8_t> encodePng(const Image& image, double exposure = 0,
                               size_t maxIdat = kMaxPngIdat);

/// Writes a PNG atomically (temporary file, then rename).
void writePng(const std::string& path, const Image& image, double exposure = 0);

}  // namespace shvol
