#include "shvol/core/error.h"

#include <gtest/gtest.h>

#include <string>

namespace shvol {

TEST(ErrorLine, LeavesOutEmptyParts) {
    EXPECT_EQ(errorLine("s.json", "media[0].albedo", "expected a number"),
              "s.json: media[0].albedo: expected a number");
    EXPECT_EQ(errorLine("", "--spp", "expected an integer"), "--spp: expected an integer");
    EXPECT_EQ(errorLine("s.json", "", "malformed JSON"), "s.json: malformed JSON");
}

// A NUL in a key ended the line where what() was read as a C string ("media (in run r0000 media"
// for the key "media\0[0].albedo"); a newline in a file name broke it in two.
TEST(ErrorLine, ControlCharactersAreWrittenAsJsonEscapes) {
    const std::string key("media\0[0].albedo", 16);
    const std::string line = errorLine("a\nb.json", key, std::string("unknown key\x7f\t"));
    EXPECT_EQ(line, "a\\u000ab.json: media\\u0000[0].albedo: unknown key\\u007f\\u0009");
    EXPECT_EQ(std::string(Error(line).what()), line);
    // UTF-8 passes unchanged; bytes that are not UTF-8 are written \xhh (a grid name from a
    // damaged file reached stderr raw): a lone continuation byte, a lead byte cut short, an
    // overlong form, a surrogate.
    EXPECT_EQ(errorLine("ü.json", "σ", "≥ 0 \xf0\x9f\x98\x80"), "ü.json: σ: ≥ 0 \xf0\x9f\x98\x80");
    EXPECT_EQ(errorLine("", "", "dens\xffity \x80 \xc3 \xc0\xaf \xed\xa0\x80 \xe2\x82"),
              "dens\\xffity \\x80 \\xc3 \\xc0\\xaf \\xed\\xa0\\x80 \\xe2\\x82");
}

}  // namespace shvol
