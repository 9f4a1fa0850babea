#include "shvol/io/ledger.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_util.h"

namespace shvol {

namespace fs = std::filesystem;

TEST(Ledger, AppendsReloadsAndWritesCsv) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger";
    fs::remove_all(dir);
    fs::create_directories(dir);
    {
        Ledger l(dir.string());
        EXPECT_TRUE(l.rows().empty());
        l.append({{"run", "r0000"}, {"rmse", 0.5}});
        l.append({{"run", "r0001"}, {"note", "a, \"b\""}});
    }
    const Ledger l(dir.string());
    ASSERT_EQ(l.rows().size(), 2u);
    ASSERT_NE(l.find("r0001"), nullptr);
    EXPECT_EQ((*l.find("r0001"))["note"], "a, \"b\"");
    EXPECT_EQ(l.find("r0002"), nullptr);
    std::ifstream f(l.csvPath());
    std::stringstream csv;
    csv << f.rdbuf();
    EXPECT_EQ(csv.str(), "rmse,run,note\n0.5,r0000,\n,r0001,\"a, \"\"b\"\"\"\n");
    for (const auto& e : fs::directory_iterator(dir))  // no temporaries left behind
        EXPECT_TRUE(e.path().filename() == "results.jsonl" || e.path().filename() == "results.csv")
            << e.path();
}

// A finished run adds a line to each file instead of rewriting them (a batch of n runs wrote
// O(n²) bytes: 1200 runs took 9.6 times as long as 300): the files keep their inodes, where a
// rewrite through a temporary and a rename would give new ones. A row with a new column rewrites
// the CSV.
TEST(Ledger, AppendsALinePerRun) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger_append";
    fs::remove_all(dir);
    fs::create_directories(dir);
    Ledger l(dir.string());
    l.append({{"run", "r0000"}, {"rmse", 0.5}});
    const auto inode = [](const fs::path& p) {
        struct stat st {};
        EXPECT_EQ(::stat(p.c_str(), &st), 0) << p;
        return st.st_ino;
    };
    const auto jsonl = inode(dir / "results.jsonl"), csv = inode(dir / "results.csv");
    l.append({{"run", "r0001"}, {"rmse", 0.25}});
    EXPECT_EQ(inode(dir / "results.jsonl"), jsonl);
    EXPECT_EQ(inode(dir / "results.csv"), csv);
    EXPECT_EQ(test::fileBytes((dir / "results.csv").string()), "rmse,run\n0.5,r0000\n0.25,r0001\n");
    l.append({{"run", "r0002"}, {"rmse", 0.125}, {"mae", 0.1}});
    EXPECT_EQ(inode(dir / "results.jsonl"), jsonl);
    EXPECT_EQ(test::fileBytes((dir / "results.csv").string()),
              "rmse,run,mae\n0.5,r0000,\n0.25,r0001,\n0.125,r0002,0.1\n");
    EXPECT_EQ(test::messageOf([&] {
                  l.append({{"run", "r0001"}});
              }),
              (dir / "results.jsonl").string() + ": run r0001: a row without a new \"run\"");
}

// What a kill can leave: a last JSONL line cut short (dropped, and the file rewritten without
// it: the run renders again), and a CSV row the JSONL does not hold (the CSV is made again).
TEST(Ledger, RepairsWhatAKillLeft) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger_kill";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "results.jsonl") << "{\"run\": \"r0000\", \"rmse\": 1}\n{\"run\": \"r00";
    std::ofstream(dir / "results.csv") << "rmse,run\n1,r0000\n2,r0001\n";
    const Ledger l(dir.string());
    ASSERT_EQ(l.rows().size(), 1u);
    EXPECT_EQ(l.find("r0001"), nullptr);
    EXPECT_EQ(test::fileBytes((dir / "results.jsonl").string()),
              "{\"run\": \"r0000\", \"rmse\": 1}\n");
    EXPECT_EQ(test::fileBytes((dir / "results.csv").string()), "rmse,run\n1,r0000\n");
}

// A last line that is a whole row without its newline (a hand-edited file) is kept and given
// its newline; blank lines, with spaces or a Windows \r, are skipped.
TEST(Ledger, KeepsAWholeLastRowAndSkipsBlankLines) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger_whole";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "results.jsonl", std::ios::binary)
        << "{\"run\": \"r0000\"}\r\n \r\n\n{\"run\": \"r0001\"}";
    const Ledger l(dir.string());
    EXPECT_EQ(l.rows().size(), 2u);
    EXPECT_NE(l.find("r0001"), nullptr);
    EXPECT_EQ(test::fileBytes((dir / "results.jsonl").string()),
              "{\"run\": \"r0000\"}\r\n \r\n\n{\"run\": \"r0001\"}\n");
}

TEST(Ledger, MalformedRowIsAnError) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger_bad";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "results.jsonl") << "{\"run\": \"r0\"}\n{\"run\": \n";
    EXPECT_EQ(test::messageOf([&] { Ledger l(dir.string()); }),
              (dir / "results.jsonl").string() + ": line 2: malformed JSON row");
}

}  // namespace shvol
