#include "shvol/core/spelling.h"

#include <gtest/gtest.h>

namespace shvol {

// The distance counts insertions, deletions, substitutions and swaps of neighbours, one each.
TEST(Spelling, EditDistanceCountsEachKindOfEditOnce) {
    EXPECT_EQ(editDistance("camera", "camera"), 0u);
    EXPECT_EQ(editDistance("camra", "camera"), 1u);    // insertion
    EXPECT_EQ(editDistance("cammera", "camera"), 1u);  // deletion
    EXPECT_EQ(editDistance("cbmera", "camera"), 1u);   // substitution
    EXPECT_EQ(editDistance("caemra", "camera"), 1u);   // swap of neighbours
    EXPECT_EQ(editDistance("", "abc"), 3u);
    EXPECT_EQ(editDistance("abc", "cba"), 2u);
}

// A typo's reach: within 2 edits and a third of the word, the nearest and the first of equals;
// nothing for a word that is known, or too short to tell.
TEST(Spelling, NearestSpellingIsWithinATyposReach) {
    const std::vector<std::string> subcommands = {"render", "bench", "batch", "report", "diff"};
    EXPECT_EQ(nearestSpelling("rendr", subcommands), "render");
    EXPECT_EQ(nearestSpelling("reprot", subcommands), "report");
    EXPECT_EQ(nearestSpelling("render", subcommands), "");     // known
    EXPECT_EQ(nearestSpelling("bach", subcommands), "batch");  // 1 edit; bench is 2
    EXPECT_EQ(nearestSpelling("dif", subcommands), "diff");
    EXPECT_EQ(nearestSpelling("df", subcommands), "");  // a third of 2 letters is 0 edits
    EXPECT_EQ(nearestSpelling("renderer", subcommands), "render");
    EXPECT_EQ(nearestSpelling("rendering", subcommands), "");  // 3 edits
    EXPECT_EQ(nearestSpelling("xyz", {}), "");
}

}  // namespace shvol
