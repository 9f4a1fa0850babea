#include "shvol/io/exr.h"

#include <gtest/gtest.h>

#include "test_util.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "shvol/core/error.h"

namespace shvol {

namespace {
std::string tmp(const std::string& name) {
    return test::privateTempPath(name);
}
using shvol::test::fileBytes;
using shvol::test::messageOf;
}  // namespace

TEST(Exr, RoundTripIsExactInFloat32) {
    Image img(7, 5);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x) img.set(x, y, Spectrum(x * 0.1, y * 1e-3, 1e5 + x * y));
    writeExr(tmp("rt.exr"), img);
    const Image back = readExr(tmp("rt.exr"));
    ASSERT_EQ(back.width, 7);
    ASSERT_EQ(back.height, 5);
    EXPECT_EQ(back.rgb, img.rgb);
}

// A luminance-only (Y) file is grey: Y goes to all three channels.
TEST(Exr, LuminanceOnlyFileIsGrey) {
    const std::string path = tmp("y.exr");
    {
        Imf::Header header(2, 1);
        header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
        Imf::OutputFile file(path.c_str(), header);
        float y[2] = {0.5f, 2.0f};
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y), sizeof(float), 0));
        file.setFrameBuffer(fb);
        file.writePixels(1);
    }
    const Image img = readExr(path);
    EXPECT_EQ(img.rgb, std::vector<float>({0.5f, 0.5f, 0.5f, 2.f, 2.f, 2.f}));
}

// A file written by OpenEXR itself, channels R, G, B (stored in name order, B first) of HALF
// values, over 3 × 2 pixels of distinct values, reads back channel for channel and pixel for
// pixel: every RGB test read shvol's own writer, which shares the reader's idea of the order
// (helper 119).
TEST(Exr, RgbFileOfAnotherWriterReadsChannelForChannel) {
    const std::string path = tmp("rgb.exr");
    float v[3][6];  // v[c][y·3 + x] = 100c + 10y + x, exact in half
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 6; ++i) v[c][i] = float(100 * c + 10 * (i / 3) + i % 3);
    {
        Imf::Header header(3, 2);
        Imf::FrameBuffer fb;
        std::vector<half> h[3];
        for (int c = 0; c < 3; ++c) {
            const char* name = c == 0 ? "R" : c == 1 ? "G" : "B";
            header.channels().insert(name, Imf::Channel(Imf::HALF));
            h[c].assign(v[c], v[c] + 6);
            fb.insert(name, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(h[c].data()),
                                       sizeof(half), 3 * sizeof(half)));
        }
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(2);
    }
    const Image img = readExr(path);
    ASSERT_EQ(img.width, 3);
    ASSERT_EQ(img.height, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
            for (int c = 0; c < 3; ++c)
                EXPECT_EQ(img.rgb[size_t(3 * (y * 3 + x) + c)], v[c][y * 3 + x])
                    << x << ", " << y << ", channel " << c;
}

// A pixel in an error is named in the file's coordinates, from its data window's corner (it was
// counted from the image's own first pixel).
TEST(Exr, BadPixelIsNamedInTheFilesCoordinates) {
    const std::string path = tmp("offset.exr");
    {
        const Imath::Box2i data(Imath::V2i(-10, 5), Imath::V2i(-9, 5));  // 2 x 1 pixels
        Imf::Header header(Imath::Box2i(Imath::V2i(-10, 0), Imath::V2i(0, 10)), data);
        header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
        Imf::OutputFile file(path.c_str(), header);
        float y[2] = {0.5f, NAN};
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, y, data, sizeof(float), 0));
        file.setFrameBuffer(fb);
        file.writePixels(1);
    }
    EXPECT_EQ(messageOf([&] { readExr(path); }), path + ": pixel (-9, 5): NaN value");
}

// A file without colour channels names those it has (it said only "no R,G,B or Y channel",
// which read the same for a file with R and G as for one with none).
TEST(Exr, MissingColourChannelsAreNamed) {
    const std::string path = tmp("rg.exr");
    {
        Imf::Header header(2, 1);
        header.channels().insert("R", Imf::Channel(Imf::FLOAT));
        header.channels().insert("G", Imf::Channel(Imf::FLOAT));
        Imf::OutputFile file(path.c_str(), header);
        float v[2] = {0.5f, 2.0f};
        Imf::FrameBuffer fb;
        for (const char* c : {"R", "G"})
            fb.insert(c, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(v), sizeof(float), 0));
        file.setFrameBuffer(fb);
        file.writePixels(1);
    }
    EXPECT_EQ(messageOf([&] { readExr(path); }),
              path + ": channels: has G, R; needs R, G and B, or Y");
}

TEST(Exr, BadFilesGiveOneClearLine) {
    EXPECT_EQ(messageOf([] { readExr(tmp("missing.exr")); }),
              tmp("missing.exr") + ": no such file");
    std::ofstream(tmp("corrupt.exr")) << "this is not an EXR file";
    EXPECT_EQ(messageOf([] {
                  readExr(tmp("corrupt.exr"));
              }).rfind(tmp("corrupt.exr") + ": not a readable OpenEXR file", 0),
              0u);
    // A file of another kind is named as such (helper 139: a stats file given to diff said
    // "not a readable OpenEXR file (… File is not an image file.)").
    std::ofstream(tmp("stats.exr")) << "\n  {\"image\": {}}";
    EXPECT_EQ(messageOf([] { readExr(tmp("stats.exr")); }),
              tmp("stats.exr") + ": the file is JSON text, not an OpenEXR image");
    std::ofstream(tmp("mesh.exr")) << "ply\nformat ascii 1.0\n";
    EXPECT_EQ(exrDamage(tmp("mesh.exr")), "the file is a PLY mesh, not an OpenEXR image");
    // (helper 140: a PNG, which tonemap writes, JSON after a byte order mark or many blanks)
    std::ofstream(tmp("image.exr")) << "\x89PNG\r\n\x1a\n" << std::string(40, '\0');
    EXPECT_EQ(exrDamage(tmp("image.exr")), "the file is a PNG image, not an OpenEXR image");
    std::ofstream(tmp("bom.exr")) << "\xEF\xBB\xBF{}";
    EXPECT_EQ(exrDamage(tmp("bom.exr")), "the file is JSON text, not an OpenEXR image");
    std::ofstream(tmp("blanks.exr")) << std::string(100, ' ') << "[1]";
    EXPECT_EQ(exrDamage(tmp("blanks.exr")), "the file is JSON text, not an OpenEXR image");
    Image img(3, 2);
    img.set(2, 1, Spectrum(NAN, 0, 0));
    writeExr(tmp("nan.exr"), img);
    EXPECT_EQ(messageOf([] { readExr(tmp("nan.exr")); }),
              tmp("nan.exr") + ": pixel (2, 1): NaN value");
    img.set(2, 1, Spectrum(0, -1, 0));
    writeExr(tmp("neg.exr"), img);
    EXPECT_EQ(messageOf([] { readExr(tmp("neg.exr")); }),
              tmp("neg.exr") + ": pixel (2, 1): negative value");
}

// Pixel data that cannot be decoded is named by the first scanline that fails: OpenEXR's message
// names no row. The last 16-row ZIP chunk of a smooth image (compressed, so its zlib stream has a
// checksum) is damaged at its end; the rows before it read.
TEST(Exr, DamagedPixelDataNamesTheScanline) {
    Image img(8, 64);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 8; ++x) img.set(x, y, Spectrum::Constant(0.25 * (x + y)));
    writeExr(tmp("damaged.exr"), img);
    std::string bytes = fileBytes(tmp("damaged.exr"));
    for (size_t i = bytes.size() - 6; i < bytes.size(); ++i) bytes[i] = char(bytes[i] ^ 0x5a);
    std::ofstream(tmp("damaged.exr"), std::ios::binary).write(bytes.data(), bytes.size());
    EXPECT_EQ(messageOf([] {
                  readExr(tmp("damaged.exr"));
              }).rfind(tmp("damaged.exr") + ": scanline 48: not readable (", 0),
              0u)
        << messageOf([] { readExr(tmp("damaged.exr")); });
    // The file is named once, first: OpenEXR's own text named it again ('Error reading pixel data
    // from image file "…"'; noted in earlier stops). So for a file cut inside its header.
    std::ofstream(tmp("cut.exr"), std::ios::binary).write(bytes.data(), 300);
    for (const char* name : {"damaged.exr", "cut.exr"}) {
        const std::string m = messageOf([&] { readExr(tmp(name)); });
        EXPECT_EQ(m.find(tmp(name), 1), std::string::npos) << m;
    }
}

// +inf (what a render writes for a mean beyond the float range) is accepted only when asked for
// (tonemap's previews); NaN and −inf never. Images to compare (diff) may hold ±inf and negative
// values, never NaN.
TEST(Exr, InfinityOnlyWhenAllowed) {
    Image img(3, 2);
    img.set(1, 0, Spectrum(INFINITY, 1, 1));
    writeExr(tmp("inf.exr"), img);
    EXPECT_EQ(messageOf([] { readExr(tmp("inf.exr")); }),
              tmp("inf.exr") + ": pixel (1, 0): infinite value");
    EXPECT_EQ(readExr(tmp("inf.exr"), ExrValues::Preview).at(1, 0)[0], INFINITY);
    img.set(1, 0, Spectrum(INFINITY, 0, 0));  // one channel beyond the float range, one dark
    writeExr(tmp("inf0.exr"), img);
    EXPECT_EQ(readExr(tmp("inf0.exr"), ExrValues::Preview).at(1, 0)[1], 0);
    img.set(1, 0, Spectrum(NAN, 1, 1));
    writeExr(tmp("nan2.exr"), img);
    EXPECT_EQ(messageOf([] { readExr(tmp("nan2.exr"), ExrValues::Preview); }),
              tmp("nan2.exr") + ": pixel (1, 0): NaN value");
    img.set(1, 0, Spectrum(1, -INFINITY, 1));
    writeExr(tmp("minf.exr"), img);
    EXPECT_EQ(messageOf([] { readExr(tmp("minf.exr"), ExrValues::Preview); }),
              tmp("minf.exr") + ": pixel (1, 0): negative infinite value");
    img.set(0, 1, Spectrum(-2, 0, 0));
    writeExr(tmp("minf.exr"), img);
    const Image compared = readExr(tmp("minf.exr"), ExrValues::Compared);
    EXPECT_EQ(compared.at(1, 0)[1], -INFINITY);
    EXPECT_EQ(compared.at(0, 1)[0], -2.f);
    EXPECT_EQ(messageOf([] { readExr(tmp("nan2.exr"), ExrValues::Compared); }),
              tmp("nan2.exr") + ": pixel (1, 0): NaN value");
}

TEST(Exr, FailedWriteLeavesNoFile) {
    const std::string path = tmp("nodir/out.exr");
    EXPECT_THROW(writeExr(path, Image(2, 2)), Error);
    EXPECT_FALSE(std::filesystem::exists(path));
}

// Found by fuzz/exr_fuzzer (UndefinedBehaviorSanitizer): readExr pointed its frame buffer at
// image.data() − dataWindow.min, a pointer outside the array (undefined even when never
// dereferenced there). A data window that does not start at (0, 0) is read correctly.
TEST(Exr, OffsetDataWindow) {
    const std::string path = tmp("offset.exr");
    const Imath::Box2i dw(Imath::V2i(-3, 5), Imath::V2i(0, 6));  // 4 × 2 pixels
    Imf::Header header(dw, dw);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    float y[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    {
        Imf::OutputFile file(path.c_str(), header);
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, y, dw));
        file.setFrameBuffer(fb);
        file.writePixels(2);
    }
    const Image img = readExr(path);
    ASSERT_EQ(img.width, 4);
    ASSERT_EQ(img.height, 2);
    for (int i = 0; i < 8; ++i)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(img.at(i % 4, i / 4)[c], y[i]);
}

/// A Y-only EXR of data window `data` (its values y, row by row) inside display window `display`.
void writeWindowed(const std::string& path, const Imath::Box2i& display, const Imath::Box2i& data,
                   const float* y) {
    Imf::Header header(display, data);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer fb;
    fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, y, data));
    file.setFrameBuffer(fb);
    file.writePixels(data.max.y - data.min.y + 1);
}

// The picture is the display window: a data window that covers part of it (a sky cropped to its
// lit half) is placed there, 0 around it, and one beyond it (overscan) is cut to it. The data
// window alone was taken for the picture: the cropped sky's lower half spread over the sphere
// (helper 68).
TEST(Exr, TheDisplayWindowIsThePicture) {
    const std::string path = tmp("window.exr");
    const float y[4] = {1, 2, 3, 4};
    // 2 × 2 data at (1, 2) in a 4 × 4 display from (0, 0).
    writeWindowed(path, Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(3, 3)),
                  Imath::Box2i(Imath::V2i(1, 2), Imath::V2i(2, 3)), y);
    Image img = readExr(path);
    ASSERT_EQ(img.width, 4);
    ASSERT_EQ(img.height, 4);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const bool in = i >= 1 && i <= 2 && j >= 2;
            EXPECT_EQ(img.at(i, j)[0], in ? y[(j - 2) * 2 + i - 1] : 0.f) << i << ", " << j;
        }
    // Overscan: 2 × 2 data from (−1, −1) around a 1 × 1 display at (0, 0): the pixel at (0, 0).
    writeWindowed(path, Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(0, 0)),
                  Imath::Box2i(Imath::V2i(-1, -1), Imath::V2i(0, 0)), y);
    img = readExr(path);
    ASSERT_EQ(img.width, 1);
    ASSERT_EQ(img.height, 1);
    EXPECT_EQ(img.at(0, 0)[0], 4.f);
    // A display window the file cannot describe is refused like a data window.
    writeWindowed(path, Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(32768, 0)),
                  Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(0, 0)), y);
    EXPECT_EQ(messageOf([&] { readExr(path); }),
              path +
                  ": display window: 32769 x 1 pixels; expected 1 to 32768 on each side, and "
                  "no more than the file can describe");
    // A data window wholly outside the display window leaves the picture without data: refused
    // (a sky of it rendered black without a word; helper 103). Touching it at a corner is data.
    writeWindowed(path, Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(3, 3)),
                  Imath::Box2i(Imath::V2i(4, 0), Imath::V2i(5, 1)), y);
    EXPECT_EQ(messageOf([&] { readExr(path); }),
              path +
                  ": data window: (4, 0) to (5, 1) lies wholly outside the display window (0, "
                  "0) to (3, 3): no pixel of the picture has data");
    writeWindowed(path, Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(3, 3)),
                  Imath::Box2i(Imath::V2i(3, 3), Imath::V2i(4, 4)), y);
    EXPECT_EQ(readExr(path).at(3, 3)[0], 1.f);
}

// Luminance and chroma channels are refused (read as Y alone they were grey).
TEST(Exr, LuminanceChromaIsRefused) {
    const std::string path = tmp("yc.exr");
    {
        Imf::Header header(2, 2);
        for (const char* c : {"Y", "RY", "BY"})
            header.channels().insert(c, Imf::Channel(Imf::FLOAT));
        Imf::OutputFile file(path.c_str(), header);
        float v[4] = {1, 1, 1, 1};
        Imf::FrameBuffer fb;
        for (const char* c : {"Y", "RY", "BY"})
            fb.insert(c, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(v), sizeof(float),
                                    2 * sizeof(float)));
        file.setFrameBuffer(fb);
        file.writePixels(2);
    }
    EXPECT_EQ(messageOf([&] { readExr(path); }),
              path +
                  ": channels: luminance and chroma (Y, RY, BY), which shvol does not "
                  "convert; save the image with R, G and B channels");
}

// A header may announce any size. A DWAB file holds 256 rows per chunk, so an 8 × 4 file whose
// data window is patched to 30000 × 256 pixels still has a valid offset table for OpenEXR, and
// readExr allocated 92 MB for it (30000 × 30000 in a tiled file: 10 GB). A data window that the
// file's bytes cannot hold, or wider than 32768 pixels, is now refused before any allocation.
TEST(Exr, DataWindowLargerThanTheFileIsRefused) {
    const std::string path = tmp("dwab.exr");
    {
        Imf::Header header(8, 4);
        header.compression() = Imf::DWAB_COMPRESSION;
        header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
        std::vector<float> y(32, 0.5f);
        Imf::OutputFile file(path.c_str(), header);
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y.data()), 4, 32));
        file.setFrameBuffer(fb);
        file.writePixels(4);
    }
    const std::string bytes = fileBytes(path);
    const std::string tag("dataWindow\0box2i\0", 17);
    const size_t at = bytes.find(tag);
    ASSERT_NE(at, std::string::npos);
    const auto withMax = [&](const std::string& name, int32_t maxX, int32_t maxY) {
        std::string b = bytes;
        std::memcpy(&b[at + tag.size() + 4 + 8], &maxX, 4);
        std::memcpy(&b[at + tag.size() + 4 + 12], &maxY, 4);
        std::ofstream(tmp(name), std::ios::binary) << b;
        return tmp(name);
    };
    const std::string huge = withMax("huge.exr", 29999, 255);
    const std::string m = messageOf([&] { readExr(huge); });
    EXPECT_EQ(m, huge + ": data window: 30000 x 256 pixels cannot be stored in " +
                     std::to_string(bytes.size()) + " bytes (damaged file)");
    const std::string wide = withMax("wide.exr", 99999, 3);
    EXPECT_EQ(messageOf([&] { readExr(wide); }).rfind(wide + ": ", 0), 0u);
}

// A header attribute whose size reaches beyond the file's end is refused before OpenEXR
// allocates it (a fuzz input's `channels` claimed 1.7 GB in 375 bytes); so is a negative size.
TEST(Exr, AttributeSizeBeyondTheFileIsRefused) {
    Image img(3, 2);
    writeExr(tmp("sizes.exr"), img);
    const std::string bytes = fileBytes(tmp("sizes.exr"));
    const std::string tag("channels\0chlist\0", 16);
    const size_t at = bytes.find(tag);
    ASSERT_NE(at, std::string::npos);
    for (const int32_t size : {1768712291, -5, int32_t(bytes.size())}) {
        std::string b = bytes;
        std::memcpy(&b[at + tag.size()], &size, 4);
        const std::string path = tmp("size.exr");
        std::ofstream(path, std::ios::binary) << b;
        const size_t left = bytes.size() - (at + tag.size() + 4);
        EXPECT_EQ(messageOf([&] { readExr(path); }),
                  path + ": header attribute 'channels': its value claims " + std::to_string(size) +
                      " bytes, the file has " + std::to_string(left) + " left (damaged file)");
    }
    // The attribute at its own size still reads.
    EXPECT_EQ(readExr(tmp("sizes.exr")).width, 3);
    // A name from the file stays on one line.
    const std::string path = tmp("name.exr");
    std::ofstream(path, std::ios::binary)
        << std::string("v/1\x01\x02\0\0\0ab\ncd\0x\0\x7f\x7f\x7f\x7f", 20);
    EXPECT_EQ(messageOf([&] { readExr(path); }),
              path +
                  ": header attribute 'ab?cd': its value claims 2139062143 bytes, the file has "
                  "0 left (damaged file)");
}

// A header cut short is named as such, at the attribute it cuts (OpenEXR's message named no place:
// "Early end of file: read 0 out of 1 requested bytes"; helper 170).
TEST(Exr, AHeaderCutShortIsNamed) {
    writeExr(tmp("whole.exr"), Image(3, 2));
    const std::string bytes = fileBytes(tmp("whole.exr"));
    const size_t channels = bytes.find("channels"), compression = bytes.find("compression");
    ASSERT_LT(channels, compression);
    const std::string path = tmp("cut.exr");
    const auto cutAt = [&](size_t n) {
        std::ofstream(path, std::ios::binary) << bytes.substr(0, n);
        return messageOf([&] { readExr(path); });
    };
    const std::string ends = ", inside the header (truncated file)";
    EXPECT_EQ(cutAt(12), path + ": header: the file ends at byte 12" + ends);
    EXPECT_EQ(cutAt(channels + 12),  // inside its type name
              path + ": header attribute 'channels': the file ends at byte " +
                  std::to_string(channels + 12) + ends);
    EXPECT_EQ(cutAt(compression + 3),  // inside the next name
              path + ": header, after attribute 'channels': the file ends at byte " +
                  std::to_string(compression + 3) + ends);
}

// In a multi-part file every header is walked: a size beyond the end in the second is refused.
/// A multi-part file of `parts` 2 × 2 parts of Y = 0.25.
void writeParts(const std::string& path, int parts) {
    std::vector<Imf::Header> headers(size_t(parts), Imf::Header(2, 2));
    for (int i = 0; i < parts; ++i) {
        headers[size_t(i)].setName("part" + std::to_string(i));
        headers[size_t(i)].setType(Imf::SCANLINEIMAGE);
        headers[size_t(i)].channels().insert("Y", Imf::Channel(Imf::FLOAT));
    }
    Imf::MultiPartOutputFile file(path.c_str(), headers.data(), parts);
    std::vector<float> y(4, 0.25f);
    for (int i = 0; i < parts; ++i) {
        Imf::OutputPart part(file, i);
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y.data()), 4, 8));
        part.setFrameBuffer(fb);
        part.writePixels(2);
    }
}

// A multi-part file of one part is read; of more, refused: it was read as its first part,
// whichever that was (an image's passes, say; helper 68).
TEST(Exr, MultiPartFilesOfOnePartOnly) {
    writeParts(tmp("one_part.exr"), 1);
    EXPECT_EQ(readExr(tmp("one_part.exr")).at(1, 1).x(), 0.25);
    writeParts(tmp("three_parts.exr"), 3);
    EXPECT_EQ(messageOf([] { readExr(tmp("three_parts.exr")); }),
              tmp("three_parts.exr") +
                  ": parts: 3 (a multi-part file), and shvol reads single-part files only, whose "
                  "part would be the picture; save the image you mean as a file of its own");
}

TEST(Exr, AttributeSizeBeyondTheFileIsRefusedInAnyPart) {
    const std::string path = tmp("parts.exr");
    writeParts(path, 2);
    std::string bytes = fileBytes(path);
    const std::string tag("channels\0chlist\0", 16);
    const size_t at = bytes.find(tag, bytes.find(tag) + 1);  // the second part's
    ASSERT_NE(at, std::string::npos);
    const int32_t size = 1 << 30;
    std::memcpy(&bytes[at + tag.size()], &size, 4);
    std::ofstream(path, std::ios::binary) << bytes;
    EXPECT_EQ(
        messageOf([&] {
            readExr(path);
        }).rfind(path + ": header attribute 'channels': its value claims 1073741824 bytes", 0),
        0u);
}

// A required attribute whose name is damaged is refused: OpenEXR put its default in its place,
// and a sky missing 'displayWindow' was read as a 64x64 picture, cropped (helper 170).
TEST(Exr, AHeaderWithoutARequiredAttributeIsRefused) {
    Image img(100, 50);
    writeExr(tmp("required.exr"), img);
    const std::string bytes = fileBytes(tmp("required.exr"));
    for (const std::string name : {"displayWindow", "dataWindow", "channels", "lineOrder"}) {
        std::string b = bytes;
        const size_t at = b.find(name + std::string(1, '\0'));
        ASSERT_NE(at, std::string::npos) << name;
        b[at + 1] = 'k';  // "dksplayWindow"
        const std::string path = tmp("damaged_name.exr");
        std::ofstream(path, std::ios::binary) << b;
        EXPECT_EQ(messageOf([&] { readExr(path); }),
                  path + ": header: no '" + name +
                      "' attribute, which every EXR header has (damaged file)");
    }
    EXPECT_EQ(readExr(tmp("required.exr")).width, 100);
    // In a multi-part file, each header (named by its number).
    writeParts(tmp("parts_required.exr"), 2);
    std::string b = fileBytes(tmp("parts_required.exr"));
    const std::string tag = std::string("displayWindow") + '\0';
    b[b.find(tag, b.find(tag) + 1) + 1] = 'k';  // the second part's
    std::ofstream(tmp("parts_required.exr"), std::ios::binary) << b;
    EXPECT_EQ(messageOf([&] { readExr(tmp("parts_required.exr")); }),
              tmp("parts_required.exr") +
                  ": header 2: no 'displayWindow' attribute, which every EXR header has (damaged "
                  "file)");
}

// Only regular files are read (a device such as /dev/zero never ends), and a file name the
// system refuses (longer than NAME_MAX) gives a shvol::Error, not std::filesystem_error.
TEST(Exr, OnlyRegularFilesAreRead) {
    EXPECT_EQ(messageOf([] { readExr("/dev/zero"); }), "/dev/zero: not a regular file");
    EXPECT_EQ(messageOf([] { readExr(testing::TempDir()); }),
              testing::TempDir() + ": not a regular file");
    const std::string longName(300, 'x');
    EXPECT_EQ(messageOf([&] { readExr(longName); }),
              longName + ": cannot read file (File name too long)");
}

}  // namespace shvol
