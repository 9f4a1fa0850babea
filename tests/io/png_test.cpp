#include "shvol/io/png.h"

#include <gtest/gtest.h>
#include <zlib.h>

namespace shvol {
namespace {
uint32_t get32(const std::vector<uint8_t>& b, size_t at) {
    return uint32_t(b[at]) << 24 | uint32_t(b[at + 1]) << 16 | uint32_t(b[at + 2]) << 8 | b[at + 3];
}
}  // namespace

// sRGB codes from the IEC 61966-2-1 formula, worked by hand: 0.5 → 1.055·0.5^(1/2.4) − 0.055 =
// 0.7354 → 187.5 → 188; 0.001 → 12.92·0.001·255 = 3.29 → 3; 0.18 → 0.4614 → 118.
TEST(Png, SrgbCodes) {
    EXPECT_EQ(srgbByte(0.0), 0);
    EXPECT_EQ(srgbByte(1.0), 255);
    EXPECT_EQ(srgbByte(7.0), 255);
    EXPECT_EQ(srgbByte(-1.0), 0);
    EXPECT_EQ(srgbByte(0.5), 188);
    EXPECT_EQ(srgbByte(0.001), 3);
    EXPECT_EQ(srgbByte(0.18), 118);
    EXPECT_EQ(srgbByte(std::nan("")), 0);
    EXPECT_EQ(srgbByte(INFINITY), 255);  // a mean beyond the float range, as render writes it
    EXPECT_EQ(srgbByte(-INFINITY), 0);
}

// The file decodes as a PNG: signature, IHDR, CRCs, and the pixels after inflating IDAT, also
// with its data cut into IDAT chunks of a few bytes (a large image's exceeded one chunk's 2^31;
// helper 152).
TEST(Png, EncodesAReadableFile) {
    Image img(3, 2);
    img.set(0, 0, Spectrum(1, 0, 0));
    img.set(2, 1, Spectrum(0.25, 0.5, 2));
    for (const size_t maxIdat : {kMaxPngIdat, size_t(5)}) {
        const std::vector<uint8_t> png = encodePng(img, 1.0, maxIdat);  // exposure +1: ×2
        const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
        ASSERT_TRUE(std::equal(sig, sig + 8, png.begin()));
        size_t at = 8;
        std::vector<uint8_t> idat;
        std::vector<std::string> types;
        while (at < png.size()) {
            const uint32_t len = get32(png, at);
            const std::string type(png.begin() + at + 4, png.begin() + at + 8);
            const uint32_t crc = uint32_t(crc32(0, &png[at + 4], len + 4));
            EXPECT_EQ(crc, get32(png, at + 8 + len)) << type;
            if (type == "IHDR") {
                EXPECT_EQ(get32(png, at + 8), 3u);
                EXPECT_EQ(get32(png, at + 12), 2u);
                EXPECT_EQ(png[at + 16], 8);  // bit depth
                EXPECT_EQ(png[at + 17], 2);  // RGB
            }
            if (type == "IDAT") {
                EXPECT_LE(len, maxIdat);
                idat.insert(idat.end(), &png[at + 8], &png[at + 8 + len]);
            }
            at += 12 + len;
            types.push_back(type);
        }
        ASSERT_GE(types.size(), 3u);
        EXPECT_EQ(types.front(), "IHDR");
        EXPECT_EQ(types.back(), "IEND");
        const size_t idats = types.size() - 2;
        EXPECT_EQ(idats, (idat.size() + maxIdat - 1) / maxIdat) << maxIdat;
        if (maxIdat == 5) EXPECT_GT(idats, 1u);
        std::vector<uint8_t> raw(2 * (1 + 9));
        uLongf size = uLongf(raw.size());
        ASSERT_EQ(uncompress(raw.data(), &size, idat.data(), uLong(idat.size())), Z_OK);
        ASSERT_EQ(size, raw.size());
        EXPECT_EQ(raw[0], 0);                                                // filter byte
        const std::vector<uint8_t> first(raw.begin() + 1, raw.begin() + 4);  // (1, 0, 0)×2
        EXPECT_EQ(first, (std::vector<uint8_t>{255, 0, 0}));
        // (0.25, 0.5, 2)×2 = (0.5, 1, 4) → (188, 255, 255)
        const std::vector<uint8_t> last(raw.begin() + 17, raw.begin() + 20);
        EXPECT_EQ(last, (std::vector<uint8_t>{188, 255, 255}));
    }
}

}  // namespace shvol
