#include "shvol/io/exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <filesystem>

#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"

namespace shvol {

Image readExr(const std::string& path) {
    if (!std::filesystem::exists(path)) fail(path, "", "file not found");
    Image img;
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i dw = file.header().dataWindow();
        img = Image(dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1);
        const Imf::ChannelList& ch = file.header().channels();
        const bool rgb = ch.findChannel("R") && ch.findChannel("G") && ch.findChannel("B");
        const bool y = ch.findChannel("Y");
        if (!rgb && !y) fail(path, "channels", "no R,G,B or Y channel");
        Imf::FrameBuffer fb;
        const size_t xs = 3 * sizeof(float), ys = xs * img.width;
        // Base pointer so that (dw.min.x, dw.min.y) lands on element 0.
        char* base = reinterpret_cast<char*>(img.rgb.data()) - dw.min.x * xs - dw.min.y * ys;
        // A luminance-only file is read into the R slot and copied to G and B below (a frame
        // buffer holds one slice per channel name).
        for (int c = 0; c < (rgb ? 3 : 1); ++c)
            fb.insert(rgb ? std::string(1, "RGB"[c]) : std::string("Y"),
                      Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        if (!rgb)
            for (size_t i = 0; i < img.rgb.size(); i += 3) img.rgb[i + 1] = img.rgb[i + 2] = img.rgb[i];
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        fail(path, "", std::string("not a readable OpenEXR file (") + e.what() + ")");
    }
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const Spectrum v = img.at(x, y);
            const std::string where =
                "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
            if (!v.allFinite()) fail(path, where, "NaN or infinite value");
            if ((v < 0).any()) fail(path, where, "negative value");
        }
    return img;
}

void writeExr(const std::string& path, const Image& image) {
    writeAtomically(path, [&](const std::string& tmp) {
        try {
            Imf::Header header(image.width, image.height);
            for (const char* c : {"R", "G", "B"})
                header.channels().insert(c, Imf::Channel(Imf::FLOAT));
            Imf::OutputFile file(tmp.c_str(), header);
            Imf::FrameBuffer fb;
            const size_t xs = 3 * sizeof(float), ys = xs * image.width;
            char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgb.data()));
            for (int c = 0; c < 3; ++c)
                fb.insert(std::string(1, "RGB"[c]),
                          Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
            file.setFrameBuffer(fb);
            file.writePixels(image.height);
        } catch (const std::exception& e) {
            fail(path, "", std::string("cannot write EXR (") + e.what() + ")");
        }
    });
}

}  // namespace shvol
