#include "shvol/core/interrupt.h"

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "shvol/core/atomic_file.h"

namespace shvol {

namespace fs = std::filesystem;

namespace {

/// What a forked child reports when it ends other than by the signal.
enum Exit { kNotInterrupted = 2, kSurvived = 3, kThrew = 4, kInterrupted = 5 };

/// Runs job() in a forked child, with SIGINT and SIGTERM unblocked and not ignored whatever the
/// test runner set, and returns its wait status. ctest runs each test in a process of its own,
/// so the temporaries' handlers are not yet installed when a job starts (the case the checkpoint
/// regression needs); a whole test binary run in one process has installed them in an earlier
/// test (removeTemporariesOnSignals does it once per process), and they are kept: reset to the
/// default, the child would never install them again, and left its temporaries (the two tests
/// below failed that way when test_core ran as one process).
template <typename Job>
int inChild(Job&& job) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        sigset_t both;
        sigemptyset(&both);
        for (const int sig : {SIGINT, SIGTERM}) {
            struct sigaction now {};
            if (::sigaction(sig, nullptr, &now) == 0 && now.sa_handler == SIG_IGN)
                std::signal(sig, SIG_DFL);
            sigaddset(&both, sig);
        }
        ::sigprocmask(SIG_UNBLOCK, &both, nullptr);
        try {
            job();
        } catch (...) {
            ::_exit(kThrew);
        }
        ::_exit(kSurvived);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
}

std::string describe(int status) {
    return WIFSIGNALED(status) ? "signal " + std::to_string(WTERMSIG(status))
                               : "exit " + std::to_string(WEXITSTATUS(status));
}

/// Writes path atomically, receiving `sig` while its temporary is half written.
void writeReceiving(const fs::path& path, int sig) {
    writeAtomically(path.string(), [&](const std::string& tmp) {
        std::ofstream(tmp) << "half";
        std::raise(sig);
    });
}

/// A fresh directory, removed with what is in it when the scope ends (also on a failure).
struct ScratchDirectory {
    explicit ScratchDirectory(const std::string& name)
        : path(fs::temp_directory_path() /
               ("shvol_interrupt_" + name + "_" + std::to_string(::getpid()))) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~ScratchDirectory() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
    /// Names in the directory other than `kept`.
    int countOthers(const std::string& kept) const {
        int n = 0;
        for (const auto& e : fs::directory_iterator(path)) n += e.path().filename() != kept;
        return n;
    }
    fs::path path;
};

}  // namespace

// A render stopped by a first signal writes what it has; a second signal meanwhile ends the
// process as the signal would, and leaves no temporary behind: also when a checkpoint was
// written during the render (the first write used to install the temporaries' handlers then,
// found the guard's own in place and left SIGINT and SIGTERM without them for good).
TEST(InterruptGuard, SecondSignalDuringTheFinalWriteRemovesTheTemporary) {
    for (const int sig : {SIGINT, SIGTERM}) {
        const ScratchDirectory dir(std::to_string(sig));
        const int status = inChild([&] {
            {
                const InterruptGuard guard;
                writeTextAtomically((dir.path / "checkpoint").string(), "during the render");
                std::raise(sig);  // the first: a clean stop
                if (!InterruptGuard::interrupted().load()) ::_exit(kNotInterrupted);
            }
            writeReceiving(dir.path / "image", sig);
        });
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig)
            << "signal " << sig << ": " << describe(status);
        EXPECT_TRUE(fs::exists(dir.path / "checkpoint"));
        EXPECT_EQ(dir.countOthers("checkpoint"), 0) << "a temporary was left in " << dir.path;
    }
}

// The same while the guard is still in place: a checkpoint written after the first signal.
TEST(InterruptGuard, SecondSignalDuringTheRenderRemovesTheTemporary) {
    const ScratchDirectory dir("during");
    const int status = inChild([&] {
        const InterruptGuard guard;
        std::raise(SIGINT);
        if (!InterruptGuard::interrupted().load()) ::_exit(kNotInterrupted);
        writeReceiving(dir.path / "checkpoint", SIGINT);
    });
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << describe(status);
    EXPECT_EQ(dir.countOthers(""), 0) << "a temporary was left in " << dir.path;
}

// Guards nest (the renders of `batch --jobs`): the signal is caught until the last one ends,
// and a guard made after the first signal (the next job) does not swallow the second.
TEST(InterruptGuard, NestedGuardsCatchOneSignalThenLetTheNextThrough) {
    const int status = inChild([] {
        {
            const InterruptGuard outer;
            { const InterruptGuard inner; }
            std::raise(SIGTERM);
            if (!InterruptGuard::interrupted().load()) ::_exit(kNotInterrupted);
        }
        const InterruptGuard next;
        std::raise(SIGTERM);
    });
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << describe(status);
}

// A job the first signal stopped exits as the shell reports that signal (128 + its number), the
// first one's: a SIGINT after a SIGHUP does not change it (a render and a batch exited 130 for
// every signal, where `report` and a signal's default gave 143 for SIGTERM).
TEST(InterruptGuard, StopExitCodeIsTheFirstSignals) {
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
        const int status = inChild([&] {
            const InterruptGuard guard;
            std::raise(sig);
            if (sig == SIGHUP) std::raise(SIGINT);  // a later one of another kind, caught too
            ::_exit(InterruptGuard::stopExitCode() & 0xff);
        });
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 128 + sig)
            << "signal " << sig << ": " << describe(status);
    }
}

// A process started with SIGINT ignored (nohup, the background of a script) keeps ignoring it.
TEST(InterruptGuard, IgnoredSignalStaysIgnored) {
    const int status = inChild([] {
        std::signal(SIGINT, SIG_IGN);
        {
            const InterruptGuard guard;
            std::raise(SIGINT);
            if (InterruptGuard::interrupted().load()) ::_exit(kInterrupted);
        }
        std::raise(SIGINT);
    });
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == kSurvived) << describe(status);
}

// Files written together (an image, its standard errors, its statistics) appear whole or not at
// all as a group: a second signal at their renames ends the process after the last one, a
// signal or a failure while they are written leaves the old files, and no temporary is left.
TEST(WriteTogether, FilesAppearAllOrNone) {
    const auto read = [](const fs::path& p) {
        std::ifstream f(p);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    const auto group = [](const fs::path& dir, const std::string& text, int stopAt, int sig) {
        std::vector<FileWrite> files;
        for (const char* name : {"image", "stderr", "stats"})
            files.push_back({(dir / name).string(), [=](const std::string& tmp) {
                                 std::ofstream(tmp) << text;
                                 if (stopAt == 1 && std::string(name) == "stderr") {
                                     if (sig == 0) throw std::runtime_error("disk full");
                                     std::raise(sig);
                                 }
                             }});
        writeTogether(files, [=](size_t i) {
            if (stopAt == 2 && i == 0) std::raise(sig);
        });
    };
    for (const int sig : {SIGINT, SIGTERM}) {
        // stopAt 1: in the second file's write (sig 0: it throws); 2: after the first rename.
        for (const auto& [stopAt, stopSig, expected] :
             {std::tuple{1, sig, "old"}, std::tuple{1, 0, "old"}, std::tuple{2, sig, "new"}}) {
            const ScratchDirectory dir("together" + std::to_string(sig));
            group(dir.path, "old", 0, 0);
            const int status = inChild([&, stopAt = stopAt, stopSig = stopSig] {
                const InterruptGuard guard;
                std::raise(sig);  // the first: a clean stop; the outputs are written next
                if (!InterruptGuard::interrupted().load()) ::_exit(kNotInterrupted);
                group(dir.path, "new", stopAt, stopSig);
            });
            const std::string what = "signal " + std::to_string(sig) + ", stop at " +
                                     std::to_string(stopAt) + " by " + std::to_string(stopSig);
            if (stopSig == 0)
                EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == kThrew)
                    << what << ": " << describe(status);
            else
                EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig)
                    << what << ": " << describe(status);
            for (const char* name : {"image", "stderr", "stats"})
                EXPECT_EQ(read(dir.path / name), expected) << what << ": " << name;
            EXPECT_EQ(dir.countOthers(""), 3) << what << ": a temporary was left in " << dir.path;
        }
    }
    // An exception at the renames leaves no temporary and signals not deferred for good (a
    // counter left raised deferred them: helper 81).
    const ScratchDirectory dir("together_throw");
    const int status = inChild([&] {
        try {
            writeTogether({{(dir.path / "a").string(),
                            [](const std::string& tmp) { std::ofstream(tmp) << "a"; }},
                           {(dir.path / "b").string(),
                            [](const std::string& tmp) { std::ofstream(tmp) << "b"; }}},
                          [](size_t) { throw std::runtime_error("afterRename"); });
        } catch (const std::runtime_error&) {
        }
        std::raise(SIGTERM);  // must end the child now
        ::_exit(kSurvived);
    });
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << describe(status);
    EXPECT_EQ(dir.countOthers("a"), 0) << "a temporary was left in " << dir.path;
    // A rename that fails midway (its directory removed) names the files it already replaced.
    const ScratchDirectory mid("together_mid");
    fs::create_directories(mid.path / "sub");
    const std::string first = (mid.path / "a").string(), second = (mid.path / "sub/b").string();
    std::string message;
    try {
        writeTogether({{first, [](const std::string& tmp) { std::ofstream(tmp) << "a"; }},
                       {second, [](const std::string& tmp) { std::ofstream(tmp) << "b"; }}},
                      [&](size_t i) {
                          if (i == 0) fs::remove_all(mid.path / "sub");
                      });
    } catch (const std::exception& e) {
        message = e.what();
    }
    EXPECT_EQ(message, second + ": cannot write file (No such file or directory); " + first +
                           " already replaced");
    EXPECT_EQ(read(first), "a");
    EXPECT_EQ(mid.countOthers("a"), 0);
}

}  // namespace shvol
