#include "shvol/io/png.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <fstream>

#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"

namespace shvol {

uint8_t srgbByte(double v) {
    v = std::isnan(v) ? 0.0 : std::clamp(v, 0.0, 1.0);  // +inf is white
    const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
    return uint8_t(std::lround(255 * s));
}

namespace {
void put32(std::vector<uint8_t>& out, uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out.push_back(uint8_t(v >> s));
}
void chunk(std::vector<uint8_t>& out, const char type[4], const uint8_t* data, size_t size) {
    put32(out, uint32_t(size));
    const size_t start = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data, data + size);
    put32(out, uint32_t(crc32(0, out.data() + start, uInt(out.size() - start))));
}
}  // namespace

std::vector<uint8_t> encodePng(const Image& img, double exposure, size_t maxIdat) {
    const double k = std::exp2(exposure);
    std::vector<uint8_t> raw;
    raw.reserve(size_t(img.height) * (1 + 3 * size_t(img.width)));
    for (int y = 0; y < img.height; ++y) {
        raw.push_back(0);  // filter type 0 (none)
        for (int x = 0; x < img.width; ++x) {
            const Spectrum c = img.at(x, y);
            for (int i = 0; i < 3; ++i) raw.push_back(srgbByte(k * c[i]));
        }
    }
    uLongf size = compressBound(uLong(raw.size()));
    std::vector<uint8_t> z(size);
    if (compress2(z.data(), &size, raw.data(), uLong(raw.size()), 6) != Z_OK)
        throw Error("PNG: zlib compression failed");
    z.resize(size);
    std::vector<uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::vector<uint8_t> ihdr;
    put32(ihdr, uint32_t(img.width));
    put32(ihdr, uint32_t(img.height));
    ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});  // 8 bits, RGB, deflate, filter 0, no interlace
    chunk(out, "IHDR", ihdr.data(), ihdr.size());
    // A chunk's length is below 2^31 (and zlib's CRC takes 32-bit lengths): the compressed data
    // of a large noisy image can be longer, and went into one IDAT (helper 152).
    maxIdat = std::clamp<size_t>(maxIdat, 1, kMaxPngIdat);
    for (size_t at = 0; at < z.size(); at += maxIdat)
        chunk(out, "IDAT", z.data() + at, std::min(maxIdat, z.size() - at));
    chunk(out, "IEND", nullptr, 0);
    return out;
}

void writePng(const std::string& path, const Image& image, double exposure) {
    const std::vector<uint8_t> bytes = encodePng(image, exposure);
    writeTextAtomically(path, std::string(bytes.begin(), bytes.end()));
}

}  // namespace shvol
