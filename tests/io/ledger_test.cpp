#include "shvol/io/ledger.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <csignal>

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
    EXPECT_EQ(csv.str(), "run,note,rmse\nr0000,,0.5\nr0001,\"a, \"\"b\"\"\",\n");
    for (const auto& e : fs::directory_iterator(dir))  // no temporaries left behind
        EXPECT_TRUE(e.path().filename() == "results.jsonl" || e.path().filename() == "results.csv")
            << e.path();
}

// results.csv puts a row's run, repeat and axes first, then seed and spp, the metrics, the times
// and the provenance (the rows' keys came alphabetically: axes among the metrics; helper 67).
// Every column that is not an axis has a place of its own.
TEST(Ledger, CsvColumnsGoRunAxesMetricsTimesProvenance) {
    for (const std::string& c : ledgerColumnsBesideAxes())
        EXPECT_NE(ledgerColumnPlace(c), kLedgerAxisPlace) << c;
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger_columns";
    fs::remove_all(dir);
    fs::create_directories(dir);
    Ledger l(dir.string());
    l.append({{"run", "r0000"},
              {"repeat", 0},
              {"spp", 4},
              {"seed", 1},
              {"rmse", 0.5},
              {"bias", 0.1},
              {"bias_ci95", 0.2},
              {"media[0].albedo", 0.9},
              {"git_revision", "abc"},
              {"total_s", 2},
              {"camera.fov", 30}});
    EXPECT_EQ(test::fileBytes(l.csvPath()),
              "run,repeat,camera.fov,media[0].albedo,seed,spp,rmse,bias,bias_ci95,total_s,"
              "git_revision\nr0000,0,30,0.9,1,4,0.5,0.1,0.2,2,abc\n");
    // With the sweep's axes given, theirs is the axes' order (a row's keys come alphabetically,
    // and the CSV had them so; helper 77), also when the ledger is read again.
    const std::string expected =
        "run,repeat,media[0].albedo,camera.fov,seed,spp,rmse,bias,bias_ci95,total_s,"
        "git_revision\nr0000,0,0.9,30,1,4,0.5,0.1,0.2,2,abc\n";
    fs::remove_all(dir);
    fs::create_directories(dir);
    {
        Ledger ordered(dir.string(), Ledger::Open::Repair, {"media[0].albedo", "camera.fov"});
        ordered.append(l.rows()[0]);
        EXPECT_EQ(test::fileBytes(ordered.csvPath()), expected);
    }
    fs::remove(dir / "results.csv");
    const Ledger again(dir.string(), Ledger::Open::Repair, {"media[0].albedo", "camera.fov"});
    EXPECT_EQ(test::fileBytes(again.csvPath()), expected);
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
    EXPECT_EQ(test::fileBytes((dir / "results.csv").string()), "run,rmse\nr0000,0.5\nr0001,0.25\n");
    l.append({{"run", "r0002"}, {"rmse", 0.125}, {"mae", 0.1}});
    EXPECT_EQ(inode(dir / "results.jsonl"), jsonl);
    EXPECT_EQ(test::fileBytes((dir / "results.csv").string()),
              "run,rmse,mae\nr0000,0.5,\nr0001,0.25,\nr0002,0.125,0.1\n");
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
    EXPECT_EQ(test::fileBytes((dir / "results.csv").string()), "run,rmse\nr0000,1\n");
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

// A write that fails part way (here at a file size limit, as at a full disk) is cut back off:
// the JSONL is as it was, the row is not in the ledger, and later rows are refused (before,
// the row stayed in memory and the next job's row followed a half line no restart could mend).
TEST(Ledger, AFailedWriteLeavesTheFileAsItWas) {
    // The failing row adds a line to the CSV, or (a new column) rewrites it.
    for (const Json& failing : {Json{{"run", "r0002"}, {"rmse", 0.125}},
                                Json{{"run", "r0002"}, {"rmse", 0.125}, {"mae", 1}}}) {
        const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger_full";
        fs::remove_all(dir);
        fs::create_directories(dir);
        const std::string jsonl = (dir / "results.jsonl").string();
        {
            Ledger l(dir.string());
            l.append({{"run", "r0000"}, {"rmse", 0.5}});
            l.append({{"run", "r0001"}, {"rmse", 0.25}});
            const std::string before = test::fileBytes(jsonl);
            ASSERT_LT(test::fileBytes(l.csvPath()).size() + 16, before.size() + 5);  // CSV fits
            std::string message;
            {
                // Room for 5 more bytes in any file; past them write(2) fails with EFBIG (the
                // SIGXFSZ that would end the process is ignored meanwhile).
                rlimit old{};
                ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
                rlimit small = old;
                small.rlim_cur = before.size() + 5;
                const auto handler = std::signal(SIGXFSZ, SIG_IGN);
                ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
                message = test::messageOf([&] { l.append(failing); });
                ::setrlimit(RLIMIT_FSIZE, &old);
                std::signal(SIGXFSZ, handler);
            }
            EXPECT_EQ(message, jsonl + ": cannot write file (File too large)") << failing;
            EXPECT_EQ(test::fileBytes(jsonl), before);
            // The CSV too (its row had been written: it kept a run the JSONL does not count).
            EXPECT_EQ(test::fileBytes(l.csvPath()), "run,rmse\nr0000,0.5\nr0001,0.25\n") << failing;
            EXPECT_EQ(l.rows().size(), 2u);
            EXPECT_EQ(l.find("r0002"), nullptr);
            EXPECT_EQ(test::messageOf([&] {
                          l.append({{"run", "r0003"}});
                      }),
                      jsonl + ": run r0003: not added: an earlier write to the ledger failed");
            EXPECT_EQ(test::fileBytes(jsonl), before);
        }
        const Ledger l(dir.string());
        EXPECT_EQ(l.rows().size(), 2u);
        EXPECT_EQ(test::fileBytes(l.csvPath()), "run,rmse\nr0000,0.5\nr0001,0.25\n");
    }
}

// One writer per directory: a second Ledger that may write is refused while the first lives (in
// this process or another: the lock is flock(2) on the directory); one that only reads is not.
TEST(Ledger, OneWriterPerDirectory) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger_lock";
    fs::remove_all(dir);
    fs::create_directories(dir);
    {
        Ledger first(dir.string());
        first.append({{"run", "r0000"}});
        EXPECT_EQ(test::messageOf([&] { Ledger second(dir.string()); }),
                  dir.string() +
                      ": another shvol batch is writing into this directory; wait for it to end "
                      "or use another output directory");
        EXPECT_EQ(Ledger(dir.string(), Ledger::Open::ReadOnly).rows().size(), 1u);
    }
    EXPECT_EQ(Ledger(dir.string()).rows().size(), 1u);  // released with the first
}

// A run in two rows (two batches that wrote into one directory before the lock) is refused:
// report would count it twice.
TEST(Ledger, ARunTwiceIsAnError) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger_twice";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "results.jsonl")
        << "{\"run\": \"r0\"}\n{\"run\": \"r1\"}\n{\"run\": \"r0\"}\n";
    EXPECT_EQ(test::messageOf([&] { Ledger l(dir.string(), Ledger::Open::ReadOnly); }),
              (dir / "results.jsonl").string() +
                  ": line 3: run r0 again (first at line 1): two batches wrote into this "
                  "directory; delete one of the two lines, or use another output directory");
}

TEST(Ledger, MalformedRowIsAnError) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_ledger_bad";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "results.jsonl") << "{\"run\": \"r0\"}\n{\"run\": \n";
    EXPECT_EQ(test::messageOf([&] { Ledger l(dir.string()); }),
              (dir / "results.jsonl").string() + ": line 2: malformed JSON row");
    // A row nested deeper than kMaxJsonDepth is refused before it is built (its walks would
    // overflow the stack, as a scene's did).
    std::ofstream(dir / "results.jsonl")
        << "{\"run\": \"r0\"}\n{\"run\": \"r1\", \"x\": " << std::string(100000, '[')
        << std::string(100000, ']') << "}\n";
    EXPECT_EQ(test::messageOf([&] { Ledger l(dir.string()); }),
              (dir / "results.jsonl").string() +
                  ": line 2: objects and arrays nested more than 256 levels deep");
    // The same limit as a scene's: 255 arrays in the row's object pass, 256 do not.
    for (const size_t arrays : {kMaxJsonDepth - 1, kMaxJsonDepth}) {
        std::ofstream(dir / "results.jsonl")
            << "{\"run\": \"r0\", \"x\": " << std::string(arrays, '[') << std::string(arrays, ']')
            << "}\n";
        EXPECT_EQ(test::messageOf([&] { Ledger l(dir.string()); }),
                  arrays < kMaxJsonDepth
                      ? "(no error)"
                      : (dir / "results.jsonl").string() +
                            ": line 1: objects and arrays nested more than 256 levels deep")
            << arrays;
    }
    // The refused Ledger released its lock (a constructor that throws runs no destructor).
    std::ofstream(dir / "results.jsonl") << "{\"run\": \"r0\"}\n";
    EXPECT_EQ(Ledger(dir.string()).rows().size(), 1u);
    // The columns the batch compares are strings (a number was an internal error in the batch).
    for (const char* key :
         {"fingerprint", "settings_fingerprint", "git_revision", "reference_fingerprint"}) {
        std::ofstream(dir / "results.jsonl")
            << "{\"run\": \"r0\"}\n{\"run\": \"r1\", \"" << key << "\": 5}\n";
        EXPECT_EQ(test::messageOf([&] { Ledger l(dir.string(), Ledger::Open::ReadOnly); }),
                  (dir / "results.jsonl").string() + ": line 2: \"" + key + "\" is not a string");
    }
}

}  // namespace shvol
