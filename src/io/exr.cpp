#include "shvol/io/exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>

#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"
#include "shvol/core/input_file.h"

namespace shvol {

namespace {

// Limits that keep a small or damaged file from making OpenEXR or readExr allocate gigabytes:
// OpenEXR checks the width and height of the data window (and tiles) against these while it reads
// the header, before it allocates anything.
constexpr int kMaxExrSide = 32768;
// An image needs more than one byte of file per kMaxExrPixelsPerByte pixels (EXR's compressions
// stay below about 200 pixels per byte even for a constant image: ZIP and DWA at zlib's ~1000:1,
// PIZ's run-length Huffman codes at ~450:1, of 6 bytes per half RGB pixel), so a header that
// announces more pixels describes data the file cannot hold.
constexpr double kMaxExrPixelsPerByte = 1024;
constexpr double kMinExrPixelLimit = 1 << 20;  // small files may still hold a 1024² constant image

// OpenEXR allocates an attribute's value at the size its header gives before it reads the value:
// a 375-byte fuzz input whose `channels` attribute claimed 1,768,712,291 bytes had it allocate
// that much (about 1 s under ASan; 4 Dec). So the headers are walked first, as the file layout
// gives them: magic and version (8 bytes), then per attribute name\0 type\0, an int32 size
// (little-endian) and the value; an empty name ends a header, and in a multi-part file (version
// bit 12) an empty header ends the list. An attribute reaching beyond the file's end is refused,
// and so are a header cut short and one without an attribute every header has; whatever else is
// wrong is left to OpenEXR to report. Returns the number of headers walked (parts; 0 for what is
// not EXR).
int checkExrHeaders(const std::string& path, uintmax_t bytes) {
    std::ifstream in(path, std::ios::binary);
    unsigned char start[8];
    if (!in.read(reinterpret_cast<char*>(start), 8) || start[0] != 0x76 || start[1] != 0x2f ||
        start[2] != 0x31 || start[3] != 0x01)
        return 0;                            // not EXR's magic number: OpenEXR says so
    const bool multipart = start[5] & 0x10;  // version bit 12
    uintmax_t at = 8;
    int headers = 0;
    // Reads a name up to its \0 (control characters kept out of the error line as '?'); false at
    // the file's end or past 255 characters.
    auto readName = [&](std::string& s) {
        s.clear();
        for (char c; in.get(c);) {
            ++at;
            if (c == 0) return true;
            if (s.size() == 255) return false;
            s += (unsigned char)c < 0x20 || c == 0x7f ? '?' : c;
        }
        return false;
    };
    std::string name, type;
    for (;;) {  // one header a turn
        int attributes = 0;
        std::set<std::string> names;
        bool ended = false;  // by its empty name
        // (A header cut short is named here: OpenEXR's message names no place, "Early end of
        // file: read 0 out of 1 requested bytes"; helper 170.)
        const auto cut = [&](const std::string& where) {
            fail(path, where,
                 in.eof() ? "the file ends at byte " + std::to_string(bytes) +
                                ", inside the header (truncated file)"
                          : "a name longer than 255 characters (damaged file)");
        };
        std::string last;  // the last attribute whose name was read whole
        for (; (ended = readName(name)) && !name.empty(); ++attributes) {
            names.insert(last = name);
            unsigned char size[4];
            if (!readName(type)) cut("header attribute '" + name + "'");
            if (!in.read(reinterpret_cast<char*>(size), 4)) cut("header attribute '" + name + "'");
            at += 4;
            const int32_t n = int32_t(uint32_t(size[0]) | uint32_t(size[1]) << 8 |
                                      uint32_t(size[2]) << 16 | uint32_t(size[3]) << 24);
            if (n < 0 || uintmax_t(n) > bytes - at)
                fail(path, "header attribute '" + name + "'",
                     "its value claims " + std::to_string(n) + " bytes, the file has " +
                         std::to_string(bytes - at) + " left (damaged file)");
            in.seekg(n, std::ios::cur);
            at += uintmax_t(n);
        }
        if (!ended) cut(attributes > 0 ? "header, after attribute '" + last + "'" : "header");
        // Attributes every EXR header has (OpenEXR's file layout): OpenEXR puts its defaults
        // in place of a missing one, so a damaged name ("dksplayWindow") read as a 64x64 sky,
        // the picture cropped to it, silently (helper 170).
        if (ended && attributes > 0)
            for (const char* required :
                 {"channels", "compression", "dataWindow", "displayWindow", "lineOrder",
                  "pixelAspectRatio", "screenWindowCenter", "screenWindowWidth"})
                if (!names.count(required))
                    fail(path, "header" + (multipart ? " " + std::to_string(headers + 1) : ""),
                         std::string("no '") + required +
                             "' attribute, which every EXR header has (damaged file)");
        headers += attributes > 0;
        if (!in || !multipart || attributes == 0) return headers;
    }
}

/// "(x0, y0) to (x1, y1)", a window's corners.
std::string boxText(const Imath::Box2i& b) {
    return "(" + std::to_string(b.min.x) + ", " + std::to_string(b.min.y) + ") to (" +
           std::to_string(b.max.x) + ", " + std::to_string(b.max.y) + ")";
}

/// The image of the file's display window, which is the picture (a lat-long sky's whole sphere),
/// from its data window's pixels `img`: 0 where the data window leaves out part of it (a file
/// cropped to its non-zero part), and the data window's pixels outside it left out (overscan).
/// The data window alone put a sky holding only its lower half over the whole sphere (helper 68).
Image inDisplayWindow(Image img, const Imath::Box2i& data, const Imath::Box2i& display,
                      const std::string& path, uintmax_t bytes) {
    if (data == display) return img;
    const int64_t w = int64_t(display.max.x) - display.min.x + 1,
                  h = int64_t(display.max.y) - display.min.y + 1;
    if (w < 1 || h < 1 || w > kMaxExrSide || h > kMaxExrSide ||
        double(w) * double(h) > std::max({kMinExrPixelLimit, kMaxExrPixelsPerByte * bytes,
                                          double(img.width) * img.height}))
        fail(path, "display window",
             std::to_string(w) + " x " + std::to_string(h) + " pixels; expected 1 to " +
                 std::to_string(kMaxExrSide) +
                 " on each side, and no more than the file can describe");
    // (the picture would be black: a sky of it rendered black without a word; helper 103)
    if (data.max.x < display.min.x || data.min.x > display.max.x || data.max.y < display.min.y ||
        data.min.y > display.max.y)
        fail(path, "data window",
             boxText(data) + " lies wholly outside the display window " + boxText(display) +
                 ": no pixel of the picture has data");
    Image out{int(w), int(h)};
    for (int64_t y = std::max(data.min.y, display.min.y); y <= std::min(data.max.y, display.max.y);
         ++y)
        for (int64_t x = std::max(data.min.x, display.min.x);
             x <= std::min(data.max.x, display.max.x); ++x)
            out.set(int(x - display.min.x), int(y - display.min.y),
                    img.at(int(x - data.min.x), int(y - data.min.y)));
    return out;
}

}  // namespace

namespace {
/// OpenEXR's message of `e` with the file's name, which the error line names first, as "the
/// file": 'Error reading pixel data from image file "out.exr". Early end of file' named it twice.
std::string openExrReason(const std::exception& e, const std::string& path) {
    std::string why = e.what();
    for (const std::string& named : {"image file \"" + path + "\"", "\"" + path + "\""})
        for (size_t at; (at = why.find(named)) != std::string::npos;)
            why.replace(at, named.size(), "the file");
    return why;
}

/// Why the file at path, which OpenEXR could not open (`e`), is no image: a file of another kind
/// named as such, by its first bytes ("the file is JSON text, not an OpenEXR image": a stats
/// file given to `diff` said "not a readable OpenEXR file (… File is not an image file.)";
/// helper 139), else OpenEXR's reason.
std::string notReadableExr(const std::exception& e, const std::string& path) {
    if (std::string other = fileOfAnotherKind(path, "an OpenEXR image"); !other.empty())
        return other;
    return "not a readable OpenEXR file (" + openExrReason(e, path) + ")";
}

/// OpenEXR's limits on what a header may claim, set once before any file is opened.
void limitExrHeaders() {
    static std::once_flag limits;
    std::call_once(limits, [] {
        Imf::Header::setMaxImageSize(kMaxExrSide, kMaxExrSide);
        Imf::Header::setMaxTileSize(kMaxExrSide, kMaxExrSide);
    });
}
}  // namespace

std::string exrDamage(const std::string& path) {
    try {
        checkExrHeaders(path, regularFileSize(path));
        limitExrHeaders();
        if (!Imf::InputFile(path.c_str()).isComplete()) return "its pixel data is cut short";
        return "";
    } catch (const std::exception& e) {  // (shvol's errors name the file; OpenEXR's too)
        return notReadableExr(e, path);
    }
}

Image readExr(const std::string& path, ExrValues values) {
    const uintmax_t bytes = regularFileSize(path);
    limitExrHeaders();
    // A multi-part file (an image and its passes, say) was read as its first part, whichever
    // that was (helper 68).
    if (const int parts = checkExrHeaders(path, bytes); parts > 1)
        fail(path, "parts",
             std::to_string(parts) +
                 " (a multi-part file), and shvol reads single-part files only, whose part "
                 "would be the picture; save the image you mean as a file of its own");
    Image img;
    int x0 = 0, y0 = 0;  // the data window's corner: errors name pixels as the file does
    Imath::Box2i dataWindow, displayWindow;
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i dw = file.header().dataWindow();
        dataWindow = dw, displayWindow = file.header().displayWindow();
        x0 = dw.min.x, y0 = dw.min.y;
        const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
        if (w < 1 || h < 1 || w > kMaxExrSide || h > kMaxExrSide)
            fail(path, "data window",
                 std::to_string(w) + " x " + std::to_string(h) + " pixels; expected 1 to " +
                     std::to_string(kMaxExrSide) + " on each side");
        if (double(w) * double(h) > std::max(kMinExrPixelLimit, kMaxExrPixelsPerByte * bytes))
            fail(path, "data window",
                 std::to_string(w) + " x " + std::to_string(h) + " pixels cannot be stored in " +
                     std::to_string(bytes) + " bytes (damaged file)");
        const Imf::ChannelList& ch = file.header().channels();
        const bool rgb = ch.findChannel("R") && ch.findChannel("G") && ch.findChannel("B");
        const bool y = ch.findChannel("Y");
        // Luminance and chroma (Y, RY, BY: OpenEXR's luminance–chroma images) read as Y alone
        // came out grey (helper 68).
        if (!rgb && (ch.findChannel("RY") || ch.findChannel("BY")))
            fail(path, "channels",
                 "luminance and chroma (Y, RY, BY), which shvol does not convert; save the image "
                 "with R, G and B channels");
        if (!rgb && !y) {
            std::string names;  // the first 8, printable ASCII (a damaged file's are bytes)
            int listed = 0;
            for (auto c = ch.begin(); c != ch.end(); ++c, ++listed) {
                if (listed == 8) {
                    names += ", …";
                    break;
                }
                std::string name = c.name();
                for (char& b : name)
                    if (b < 0x20 || b > 0x7e) b = '?';
                names += (names.empty() ? "" : ", ") + name;
            }
            fail(path, "channels",
                 "has " + (names.empty() ? std::string("none") : names) +
                     "; needs R, G and B, or Y");
        }
        img = Image(int(w), int(h));
        Imf::FrameBuffer fb;
        const size_t xs = 3 * sizeof(float), ys = xs * img.width;
        // Slice::Make places (dw.min.x, dw.min.y) on the given element (computing the slice's
        // base address outside the array without pointer arithmetic, which would be undefined).
        // A luminance-only file is read into the R slot and copied to G and B below (a frame
        // buffer holds one slice per channel name).
        for (int c = 0; c < (rgb ? 3 : 1); ++c)
            fb.insert(rgb ? std::string(1, "RGB"[c]) : std::string("Y"),
                      Imf::Slice::Make(Imf::FLOAT, img.rgb.data() + c, dw, xs, ys));
        file.setFrameBuffer(fb);
        try {
            file.readPixels(dw.min.y, dw.max.y);
        } catch (const std::exception& e) {
            // OpenEXR's message names no row: the first one that cannot be read is found again,
            // row by row in a fresh reader (OpenEXR keeps the chunk it decoded last, so this
            // costs about one more read of the rows before it).
            const std::string why = openExrReason(e, path);
            int row = dw.min.y;
            bool opened = false, failed = false;
            try {
                Imf::InputFile again(path.c_str());
                again.setFrameBuffer(fb);
                opened = true;
                for (; row <= dw.max.y; ++row) again.readPixels(row, row);
            } catch (const std::exception&) {
                failed = opened;  // (not reopened: the first error is the one to report)
            }
            if (failed) fail(path, "scanline " + std::to_string(row), "not readable (" + why + ")");
            throw;
        }
        if (!rgb)
            for (size_t i = 0; i < img.rgb.size(); i += 3)
                img.rgb[i + 1] = img.rgb[i + 2] = img.rgb[i];
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        fail(path, "", notReadableExr(e, path));
    }
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const Spectrum v = img.at(x, y);
            if (v.allFinite() && (v >= 0).all()) continue;  // (most pixels: nothing to say)
            const std::string where = "pixel (" + std::to_string(int64_t(x0) + x) + ", " +
                                      std::to_string(int64_t(y0) + y) + ")";
            if (v.hasNaN()) fail(path, where, "NaN value");
            if (values == ExrValues::Compared) continue;
            if (values == ExrValues::Reference) {
                if (!v.allFinite())
                    fail(path, where,
                         "infinite value: every run's error against this reference would be "
                         "infinite");
                continue;
            }
            if ((v < 0).any())
                fail(path, where,
                     (v == -INFINITY).any() ? "negative infinite value" : "negative value");
            if (!v.allFinite() && values != ExrValues::Preview) fail(path, where, "infinite value");
        }
    return inDisplayWindow(std::move(img), dataWindow, displayWindow, path, bytes);
}

void writeExrTo(const std::string& tmp, const Image& image, const std::string& path) {
    // Through a stream of ours (writeStreamTo): OpenEXR's OutputFile writes the scan lines'
    // offsets as it is destroyed, and nothing it writes then is checked.
    writeStreamTo(tmp, path, "EXR", [&](std::ofstream& os) {
        Imf::StdOFStream stream(os, tmp.c_str());
        Imf::Header header(image.width, image.height);
        for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
        Imf::OutputFile file(stream, header);
        Imf::FrameBuffer fb;
        const size_t xs = 3 * sizeof(float), ys = xs * image.width;
        char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgb.data()));
        for (int c = 0; c < 3; ++c)
            fb.insert(std::string(1, "RGB"[c]),
                      Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
        file.setFrameBuffer(fb);
        file.writePixels(image.height);
    });
}

void writeExr(const std::string& path, const Image& image) {
    writeAtomically(path, [&](const std::string& tmp) { writeExrTo(tmp, image, path); });
}

}  // namespace shvol
