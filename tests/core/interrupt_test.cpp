#include "shvol/core/interrupt.h"

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

#include "shvol/core/atomic_file.h"

namespace shvol {

namespace fs = std::filesystem;

namespace {

/// What a forked child reports when it ends other than by the signal.
enum Exit { kNotInterrupted = 2, kSurvived = 3 };

/// Runs job() in a forked child and returns its wait status.
template <typename Job>
int inChild(Job&& job) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        job();
        ::_exit(kSurvived);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
}

/// Writes path atomically, receiving `sig` while its temporary is half written.
void writeReceiving(const fs::path& path, int sig) {
    writeAtomically(path.string(), [&](const std::string& tmp) {
        std::ofstream(tmp) << "half";
        std::raise(sig);
    });
}

fs::path freshDirectory(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("shvol_interrupt_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

}  // namespace

// A render stopped by a first signal writes what it has; a second signal meanwhile ends the
// process as the signal would, and leaves no temporary behind: also when a checkpoint was
// written during the render (the first write used to install the temporaries' handlers then,
// found the guard's own in place and left SIGINT and SIGTERM without them for good).
TEST(InterruptGuard, SecondSignalDuringTheFinalWriteRemovesTheTemporary) {
    for (const int sig : {SIGINT, SIGTERM}) {
        const fs::path dir = freshDirectory(std::to_string(sig));
        const int status = inChild([&] {
            {
                const InterruptGuard guard;
                writeTextAtomically((dir / "checkpoint").string(), "during the render");
                std::raise(sig);  // the first: a clean stop
                if (!InterruptGuard::interrupted().load()) ::_exit(kNotInterrupted);
            }
            writeReceiving(dir / "image", sig);
        });
        ASSERT_TRUE(WIFSIGNALED(status)) << "signal " << sig << ", exit " << WEXITSTATUS(status);
        EXPECT_EQ(WTERMSIG(status), sig);
        EXPECT_TRUE(fs::exists(dir / "checkpoint"));
        EXPECT_FALSE(fs::exists(dir / "image"));
        int left = 0;
        for (const auto& e : fs::directory_iterator(dir))
            left += e.path().filename() != "checkpoint";
        EXPECT_EQ(left, 0) << "a temporary was left in " << dir;
        fs::remove_all(dir);
    }
}

// The same while the guard is still in place: a checkpoint written after the first signal.
TEST(InterruptGuard, SecondSignalDuringTheRenderRemovesTheTemporary) {
    const fs::path dir = freshDirectory("during");
    const int status = inChild([&] {
        const InterruptGuard guard;
        std::raise(SIGINT);
        if (!InterruptGuard::interrupted().load()) ::_exit(kNotInterrupted);
        writeReceiving(dir / "checkpoint", SIGINT);
    });
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit " << WEXITSTATUS(status);
    EXPECT_EQ(WTERMSIG(status), SIGINT);
    EXPECT_TRUE(fs::is_empty(dir));
    fs::remove_all(dir);
}

}  // namespace shvol
