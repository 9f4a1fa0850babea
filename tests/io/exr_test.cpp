#include "shvol/io/exr.h"

#include <gtest/gtest.h>

#include "test_util.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <filesystem>
#include <fstream>

#include "shvol/core/error.h"

namespace shvol {

namespace {
std::string tmp(const std::string& name) {
    return testing::TempDir() + "/shvol_exr_" + name;
}
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

TEST(Exr, BadFilesGiveOneClearLine) {
    EXPECT_EQ(messageOf([] { readExr(tmp("missing.exr")); }),
              tmp("missing.exr") + ": file not found");
    std::ofstream(tmp("corrupt.exr")) << "this is not an EXR file";
    EXPECT_EQ(messageOf([] {
                  readExr(tmp("corrupt.exr"));
              }).rfind(tmp("corrupt.exr") + ": not a readable OpenEXR file", 0),
              0u);
    Image img(3, 2);
    img.set(2, 1, Spectrum(NAN, 0, 0));
    writeExr(tmp("nan.exr"), img);
    EXPECT_EQ(messageOf([] { readExr(tmp("nan.exr")); }),
              tmp("nan.exr") + ": pixel (2, 1): NaN or infinite value");
    img.set(2, 1, Spectrum(0, -1, 0));
    writeExr(tmp("neg.exr"), img);
    EXPECT_EQ(messageOf([] { readExr(tmp("neg.exr")); }),
              tmp("neg.exr") + ": pixel (2, 1): negative value");
}

TEST(Exr, FailedWriteLeavesNoFile) {
    const std::string path = tmp("nodir/out.exr");
    EXPECT_THROW(writeExr(path, Image(2, 2)), Error);
    EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace shvol
