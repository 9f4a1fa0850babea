#include "shvol/core/atomic_file.h"

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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

// The temporaries of processes ended by SIGKILL (kill -9, mpirun's kill a second after a Ctrl-C;
// helper 147) are removed, for the names the caller owns; one of a process that runs (this one's
// parent), other names, names that only look alike and what is not a regular file stay.
TEST(AtomicFile, TemporariesOfEndedProcessesAreRemoved) {
    const ScratchDir dir;
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    ASSERT_GT(child, 0);
    int status = 0;
    ::waitpid(child, &status, 0);  // reaped: its PID runs nothing now
    const std::string dead = std::to_string(child);
    const std::vector<std::string> stay = {"out.ck.tmp" + std::to_string(::getppid()),
                                           "out.ck.tmpx1",
                                           "out.ck.tmp",
                                           "other.ck.tmp" + dead,
                                           "out.ck.tmp-" + dead,
                                           "out.ck.tmp" + dead + ".txt",
                                           "out.ck.tmp0" + dead};
    for (const std::string& name : stay) std::ofstream(dir.path / name) << "keep";
    fs::create_directory(dir.path / ("out.ck.stats.tmp" + dead));  // (a directory: kept)
    // (a link to a regular file: it and its target stay)
    fs::create_symlink(dir.path / ("other.ck.tmp" + dead), dir.path / ("out.exr.tmp" + dead));
    for (const char* name : {"out.ck", "out.exr.stats.json"})
        std::ofstream(dir.path / (name + (".tmp" + dead))) << "left by kill -9";
    removeStaleTemporaries(dir.path.string(),
                           [](const std::string& name) { return name.rfind("out.", 0) == 0; });
    EXPECT_FALSE(fs::exists(dir.path / ("out.ck.tmp" + dead)));
    EXPECT_FALSE(fs::exists(dir.path / ("out.exr.stats.json.tmp" + dead)));
    for (const std::string& name : stay) EXPECT_TRUE(fs::exists(dir.path / name)) << name;
    EXPECT_TRUE(fs::is_directory(dir.path / ("out.ck.stats.tmp" + dead)));
    EXPECT_TRUE(fs::is_symlink(dir.path / ("out.exr.tmp" + dead)));
    EXPECT_EQ(contents(dir.path / ("other.ck.tmp" + dead)), "keep");
}

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
// A directory that cannot be written into is named as such, itself as "it" ("directory it is
// not writable" before 6 Dec; helper 100), and a directory named "it" by its name (review).
// Checked in a child process, as an unprivileged user (root may write anywhere) and in the
// scratch directory (relative names).
TEST(AtomicFile, UnwritableDirectoriesAreNamed) {
    const ScratchDir d;
    const fs::path ro = d.path / "it";
    fs::create_directories(ro);
    ::chmod(d.path.c_str(), 0755);
    ::chmod(ro.c_str(), 0555);
    int pipe[2];
    ASSERT_EQ(::pipe(pipe), 0);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::close(pipe[0]);
        std::string text = "setuid or chdir failed";
        if ((::geteuid() != 0 || ::setuid(65534) == 0) && ::chdir(d.path.c_str()) == 0)
            text = outputDirectoryProblem(ro.string()) + "|" +
                   outputDirectoryProblem((ro / "runs").string()) + "|" +
                   outputFileProblem("it/x.exr") + "|" + outputDirectoryProblem("it");
        (void)!::write(pipe[1], text.data(), text.size());
        ::_exit(0);
    }
    ::close(pipe[1]);
    std::string text;
    char buffer[512];
    for (ssize_t n; (n = ::read(pipe[0], buffer, sizeof buffer)) > 0;) text.append(buffer, n);
    ::close(pipe[0]);
    ::waitpid(pid, nullptr, 0);
    const std::string denied = " is not writable (Permission denied)";
    EXPECT_EQ(text, "it" + denied + "|directory " + ro.string() + denied + "|directory it" +
                        denied + "|it" + denied);
}

// Where the permission bits let root write but no file can be made (sysfs), the directory is
// named as not writable before the work: access() said yes, and a render to /sys/o.exr failed
// only once it had finished (helper 116). The file made to find out is removed.
TEST(AtomicFile, DirectoriesWherePermissionBitsMisleadAreNamed) {
    const ScratchDir d;
    EXPECT_EQ(outputFileProblem((d.path / "x.exr").string()), "");
    EXPECT_EQ(outputDirectoryProblem((d.path / "runs").string()), "");
    EXPECT_TRUE(fs::is_empty(d.path));
    std::error_code ec;
    if (!fs::is_directory("/sys", ec) || ::access("/sys", W_OK | X_OK) != 0 ||
        std::ofstream("/sys/shvol-test-probe"))
        GTEST_SKIP() << "/sys is not a directory whose bits alone allow writing here";
    EXPECT_EQ(outputFileProblem("/sys/o.exr").rfind("directory /sys is not writable (", 0), 0u)
        << outputFileProblem("/sys/o.exr");
    EXPECT_EQ(outputDirectoryProblem("/sys/runs").rfind("directory /sys is not writable (", 0), 0u);
}

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
