#include "shvol/core/atomic_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <string>

#include "shvol/core/error.h"
#include "test_util.h"

namespace shvol {

namespace fs = std::filesystem;

namespace {

/// A directory of its own under the test's temporary directory (test::privateTempPath), removed
/// at the end.
struct ScratchDir {
    fs::path path = test::privateTempPath("dir");
    ScratchDir() {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~ScratchDir() { fs::remove_all(path); }
};

std::string contents(const fs::path& p) {
    return test::fileBytes(p.string());
}

}  // namespace

// A symbolic link named as an output keeps pointing where it did, and its target gets the new
// contents (the rename used to replace the link by a regular file), for a relative link into
// another directory, a chain of two links and a link whose target does not exist yet.
TEST(AtomicFile, WritesThroughSymbolicLinks) {
    const ScratchDir dir;
    fs::create_directories(dir.path / "a");
    std::ofstream(dir.path / "a" / "target.txt") << "old";
    fs::create_symlink("a/target.txt", dir.path / "link");
    fs::create_symlink("link", dir.path / "link2");
    fs::create_symlink("a/new.txt", dir.path / "dangling");
    for (const char* name : {"link", "link2", "dangling"}) {
        const fs::path p = dir.path / name;
        EXPECT_EQ(outputFileProblem(p.string()), "") << name;
        writeTextAtomically(p.string(), std::string("through ") + name);
        EXPECT_TRUE(fs::is_symlink(p)) << name;
        EXPECT_EQ(contents(p), std::string("through ") + name);
    }
    EXPECT_EQ(contents(dir.path / "a" / "target.txt"), "through link2");
    EXPECT_EQ(contents(dir.path / "a" / "new.txt"), "through dangling");
    // No temporary is left beside a link or its target.
    for (const fs::path& d : {dir.path, dir.path / "a"})
        for (const auto& e : fs::directory_iterator(d))
            EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

// A FIFO (or a device: /dev/null is only checked here, never written) is refused before
// anything is written, and stays what it was: the rename used to replace it by a regular file,
// which as root replaced /dev/null itself. A link to one is refused too.
TEST(AtomicFile, RefusesToReplaceWhatIsNotARegularFile) {
    const ScratchDir dir;
    const fs::path fifo = dir.path / "fifo";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    fs::create_symlink("fifo", dir.path / "to_fifo");
    const std::string expected =
        "is not a regular file (a device, FIFO or socket: it would be replaced)";
    EXPECT_EQ(outputFileProblem("/dev/null"), expected);
    for (const fs::path& p : {fifo, dir.path / "to_fifo"}) {
        EXPECT_EQ(outputFileProblem(p.string()), expected) << p;
        bool called = false;
        try {
            writeAtomically(p.string(), [&](const std::string&) { called = true; });
            ADD_FAILURE() << p << " was written";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()), p.string() + ": cannot write: " + expected);
        }
        EXPECT_FALSE(called) << p;
        EXPECT_TRUE(fs::is_fifo(fifo));
    }
    // A loop of links (the review's case) is refused, and stays a loop.
    fs::create_symlink("loop_b", dir.path / "loop_a");
    fs::create_symlink("loop_a", dir.path / "loop_b");
    const std::string loop = (dir.path / "loop_a").string();
    EXPECT_EQ(outputFileProblem(loop).rfind("cannot be resolved (", 0), 0u)
        << outputFileProblem(loop);
    EXPECT_THROW(writeTextAtomically(loop, "x"), Error);
    EXPECT_TRUE(fs::is_symlink(dir.path / "loop_a"));
    // A directory is refused by both too.
    EXPECT_EQ(outputFileProblem(dir.path.string()), "is a directory");
    EXPECT_THROW(writeTextAtomically(dir.path.string(), "x"), Error);
    EXPECT_TRUE(fs::is_directory(dir.path));
}

}  // namespace shvol
