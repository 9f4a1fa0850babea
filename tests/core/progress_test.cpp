#include "shvol/core/progress.h"

#include <gtest/gtest.h>

namespace shvol {

// The line fits the terminal whatever its width, so it redraws instead of wrapping; the bar
// shows the fraction and disappears when there is no room for it.
TEST(Progress, LineFitsTheTerminal) {
    for (int columns : {10, 20, 30, 40, 80, 200})
        for (bool final : {false, true}) {
            const std::string line = progressLine("render", 0.42, 12.3, final, columns);
            EXPECT_LE(int(line.size()), columns - 1) << columns << ": " << line;
        }
    const std::string wide = progressLine("render", 0.5, 10, false, 80);
    EXPECT_EQ(wide, "render [===============               ]  50% ETA 10s");
    // 30 columns: 29 usable − "render" − " 50% ETA 10s" (13) − " []" leaves a bar of 7.
    EXPECT_EQ(progressLine("render", 0.5, 10, false, 30), "render [===    ]  50% ETA 10s");
    // 20 columns: no room for a bar.
    EXPECT_EQ(progressLine("render", 0.5, 10, false, 20), "render  50% ETA 10s");
    EXPECT_EQ(progressLine("render", 1, 3.25, true, 80),
              "render [==============================] 100% 3.2s");
}

}  // namespace shvol
