#include "shvol/io/ledger.h"

#include <gtest/gtest.h>

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

TEST(Ledger, MalformedRowIsAnError) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger_bad";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "results.jsonl") << "{\"run\": \"r0\"}\n{\"run\": \n";
    EXPECT_EQ(test::messageOf([&] { Ledger l(dir.string()); }),
              (dir / "results.jsonl").string() + ": line 2: malformed JSON row");
}

}  // namespace shvol
