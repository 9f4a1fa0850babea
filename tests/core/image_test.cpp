#include "shvol/core/image.h"

#include <gtest/gtest.h>

#include <cmath>

namespace shvol {

TEST(Image, StatisticsSkipNonFiniteValues) {
    Image img(2, 2);
    img.set(0, 0, Spectrum(1, 2, 3));
    img.set(1, 0, Spectrum(3, -2, 5));
    img.set(0, 1, Spectrum(NAN, 4, 1));
    img.set(1, 1, Spectrum(INFINITY, 0, 3));
    const ImageStatistics st = imageStatistics(img);
    EXPECT_EQ(st.nonFinite, 2);
    EXPECT_DOUBLE_EQ(st.mean[0], 2.0);  // the finite red values 1 and 3
    EXPECT_DOUBLE_EQ(st.min[0], 1.0);
    EXPECT_DOUBLE_EQ(st.max[0], 3.0);
    EXPECT_DOUBLE_EQ(st.mean[1], 1.0);
    EXPECT_DOUBLE_EQ(st.min[1], -2.0);
    EXPECT_DOUBLE_EQ(st.max[2], 5.0);
    EXPECT_DOUBLE_EQ(st.mean[2], 3.0);
}

// A channel without a finite value has no mean, minimum or maximum: NaN (null in the stats),
// not the 0 they read before (an image all overflowing had a mean of 0; helper 68).
TEST(Image, StatisticsOfAChannelWithoutFiniteValuesAreUnknown) {
    Image img(1, 1);
    img.set(0, 0, Spectrum(NAN, INFINITY, 1));
    const ImageStatistics st = imageStatistics(img);
    EXPECT_EQ(st.nonFinite, 2);
    for (int c = 0; c < 2; ++c) {
        EXPECT_TRUE(std::isnan(st.mean[c]));
        EXPECT_TRUE(std::isnan(st.min[c]));
        EXPECT_TRUE(std::isnan(st.max[c]));
    }
    EXPECT_EQ(st.mean[2], 1.0);
}

}  // namespace shvol
