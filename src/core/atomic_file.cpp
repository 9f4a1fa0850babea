#include "shvol/core/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <system_error>

#include "shvol/core/error.h"

namespace shvol {

namespace {

/// The temporaries being written, for the signal handler: a slot is claimed, its path copied,
/// then armed; the handler reads only armed slots (lock-free flags, unlink is async-signal-safe).
struct TemporarySlot {
    std::atomic<bool> claimed{false}, armed{false};
    char path[4096];
};
constexpr int kSlots = 64;
TemporarySlot gSlots[kSlots];
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler reads the flags");

/// writeTogether's renames under way, and a signal that came during them (0: none): it ends the
/// process once the last of them is done, so a group of files is renamed whole or not at all.
std::atomic<int> gRenaming{0}, gDeferredSignal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads them");

/// Ends the process by `sig` as it would have, without the temporaries.
void dieRemovingTemporaries(int sig) {
    for (TemporarySlot& s : gSlots)
        if (s.armed.load()) ::unlink(s.path);
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

/// SIGTERM, SIGHUP or SIGINT ends the process as it would have, without the temporaries; during
/// writeTogether's renames, once they are done. (Whoever of this handler and the renames' end
/// takes the deferred signal out of gDeferredSignal acts on it, so it is neither lost nor taken
/// twice, whichever thread the signal came to.)
extern "C" void removeTemporariesAndDie(int sig) {
    if (gRenaming.load() > 0) {
        gDeferredSignal.store(sig);
        if (gRenaming.load() > 0) return;
        if (gDeferredSignal.exchange(0) == 0) return;  // the renames' end took it
    }
    dieRemovingTemporaries(sig);
}

}  // namespace

void removeTemporariesOnSignals() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (const int sig : {SIGTERM, SIGHUP, SIGINT}) {
            struct sigaction old {};
            if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_DFL)
                std::signal(sig, removeTemporariesAndDie);
        }
    });
}

namespace {

/// Registers tmp for removal on a signal while it lives (not at all if the slots are taken or the
/// path is too long: the temporary is then only left behind, as before).
class TemporaryGuard {
  public:
    explicit TemporaryGuard(const std::string& tmp) {
        removeTemporariesOnSignals();
        if (tmp.size() >= sizeof(TemporarySlot::path)) return;
        for (TemporarySlot& s : gSlots) {
            bool expected = false;
            if (!s.claimed.compare_exchange_strong(expected, true)) continue;
            std::memcpy(s.path, tmp.c_str(), tmp.size() + 1);
            s.armed.store(true);
            slot_ = &s;
            return;
        }
    }
    ~TemporaryGuard() {
        if (!slot_) return;
        slot_->armed.store(false);
        slot_->claimed.store(false);
    }
    TemporaryGuard(const TemporaryGuard&) = delete;
    TemporaryGuard& operator=(const TemporaryGuard&) = delete;

  private:
    TemporarySlot* slot_ = nullptr;
};

/// The nearest of `path` (made absolute) and its ancestors that exists; empty if none does (the
/// current directory removed).
std::filesystem::path nearestExisting(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::path p = fs::absolute(path, ec);
    if (ec) return {};
    while (!fs::exists(p, ec) && p.has_relative_path()) p = p.parent_path();
    return fs::exists(p, ec) ? p : fs::path();
}

/// 0 if a file can be made in the directory `dir` and removed again, else the errno of the step
/// that failed. access() answers from the permission bits, which root passes where no file can
/// be made (sysfs, /proc) or removed (an append-only directory): the probe says so before the
/// work, not after it (helper 116: a render to /sys/o.exr failed only once it had finished).
/// Once per directory and process: a batch checks many outputs in one (helper 120).
int probeWritable(const std::filesystem::path& dir) {
    static std::mutex mutex;
    static std::map<std::string, int> known;
    std::error_code ec;
    const std::string key = std::filesystem::absolute(dir, ec).lexically_normal().string();
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = known.find(key); it != known.end()) return it->second;
    std::string probe = (dir / ".shvol-probe-XXXXXX").string();
    int error = 0;
    if (const int fd = ::mkostemp(probe.data(), O_CLOEXEC); fd < 0) {
        error = errno;
    } else {
        ::close(fd);
        if (::unlink(probe.c_str()) != 0) error = errno;
    }
    return known[key] = error;
}

/// Why files cannot be made in the existing `dir`: not a directory, or not writable. `name` is
/// how the message names it, empty for "it" (the path the user gave).
std::string directoryProblem(const std::filesystem::path& dir, const std::string& name) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        return (name.empty() ? "it" : name) + " is not a directory";
    const int error = ::access(dir.c_str(), W_OK | X_OK) != 0 ? errno : probeWritable(dir);
    if (error != 0)
        return (name.empty() ? "it" : "directory " + name) + " is not writable (" +
               std::generic_category().message(error) + ")";
    return "";
}

/// Why the file at `target` (a link's target) cannot be replaced by a rename: "is a directory",
/// or "is not a regular file (…)" for a device, FIFO or socket; empty otherwise (none there too).
std::string replacementProblem(const std::filesystem::path& target) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(target, ec);
    // (a loop of links, or one that cannot be read: the rename would replace the link)
    if (ec && ec != std::errc::no_such_file_or_directory)
        return "cannot be resolved (" + ec.message() + ")";
    if (fs::is_directory(st)) return "is a directory";
    if (fs::exists(st) && !fs::is_regular_file(st))
        return "is not a regular file (a device, FIFO or socket: it would be replaced)";
    return "";
}

}  // namespace

std::filesystem::path linkTarget(const std::string& path) {
    namespace fs = std::filesystem;
    fs::path p = path;
    std::error_code ec;
    for (int i = 0; i < 40 && fs::is_symlink(p, ec); ++i) {
        const fs::path next = fs::read_symlink(p, ec);
        if (ec) break;
        p = next.is_absolute() ? next : p.parent_path() / next;
    }
    return p;
}

std::string outputFileProblem(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path target = linkTarget(path);
    const fs::path parent = target.parent_path();
    const fs::path dir = parent.empty() ? fs::path(".") : parent;
    if (!fs::exists(dir, ec)) {
        const fs::path up = nearestExisting(dir.string());
        if (!up.empty() && !fs::is_directory(up, ec)) return up.string() + " is not a directory";
        return "directory " + dir.string() + " does not exist";
    }
    if (std::string problem = directoryProblem(dir, dir.string()); !problem.empty()) return problem;
    return replacementProblem(target);
}

std::string outputDirectoryProblem(const std::string& path) {
    const std::filesystem::path up = nearestExisting(path);
    if (up.empty()) return "cannot be made (no part of it exists)";
    std::error_code ec;
    const bool itself = std::filesystem::equivalent(up, path, ec);
    return directoryProblem(up, itself ? "" : up.string());
}

void failWriting(const std::string& path, int error) {
    fail(path, "",
         error == 0 ? "cannot write file"
                    : "cannot write file (" + std::generic_category().message(error) + ")");
}

namespace {
/// Flushes a file's data, or a directory's entries, to the disk (fsync, retried when a signal
/// interrupts it); the error number, or 0. A rename is durable only once the data it puts in place
/// are: without it a power cut could leave a checkpoint renamed into place and empty, and the
/// render's work since it started lost (helper 71).
int syncToDisk(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return errno;
    int error = 0;
    while (::fsync(fd) != 0)
        if (errno != EINTR) {
            error = errno;
            break;
        }
    ::close(fd);
    return error;
}
}  // namespace

void writeTogether(const std::vector<FileWrite>& files,
                   const std::function<void(size_t)>& afterRename) {
    // A symbolic link keeps pointing where it did and its target gets the new contents (the
    // rename would replace the link itself); a device, FIFO or socket is never replaced.
    std::vector<std::string> targets, temporaries;
    for (const FileWrite& file : files) {
        targets.push_back(linkTarget(file.path).string());
        if (const std::string problem = replacementProblem(targets.back()); !problem.empty())
            fail(file.path, "", "cannot write: " + problem);
        temporaries.push_back(targets.back() + ".tmp" + std::to_string(::getpid()));
    }
    std::vector<std::unique_ptr<TemporaryGuard>> guards;
    const auto removeFrom = [&](size_t first) {
        for (size_t i = first; i < temporaries.size(); ++i) std::remove(temporaries[i].c_str());
    };
    try {
        for (size_t i = 0; i < files.size(); ++i) {
            guards.push_back(std::make_unique<TemporaryGuard>(temporaries[i]));
            files[i].write(temporaries[i]);
            if (const int error = syncToDisk(temporaries[i]); error != 0)
                failWriting(files[i].path, error);
        }
    } catch (...) {
        removeFrom(0);
        throw;
    }
    // A signal now ends the process after the last rename, not between two: an image beside the
    // statistics of the render before it (a second Ctrl-C as a stopped render wrote them). A
    // guard, so that no exception (afterRename's) leaves signals deferred for good.
    struct Renaming {
        Renaming() { ++gRenaming; }
        ~Renaming() {
            if (--gRenaming == 0)
                if (const int sig = gDeferredSignal.exchange(0); sig != 0)
                    dieRemovingTemporaries(sig);
        }
    };
    int error = 0;
    size_t failed = files.size();
    {
        const Renaming renaming;
        try {
            for (size_t i = 0; i < files.size() && failed == files.size(); ++i)
                if (std::rename(temporaries[i].c_str(), targets[i].c_str()) != 0)
                    error = errno, failed = i;
                else if (afterRename)
                    afterRename(i);
        } catch (...) {
            removeFrom(0);  // (the renamed ones are gone from their temporaries' names)
            throw;
        }
    }
    // The renames themselves, each directory once (one that cannot be synced, on some file
    // systems, is left so).
    std::set<std::string> directories;
    for (size_t i = 0; i < std::min(failed, files.size()); ++i) {
        const std::filesystem::path parent = std::filesystem::path(targets[i]).parent_path();
        directories.insert(parent.empty() ? std::string(".") : parent.string());
    }
    for (const std::string& directory : directories) syncToDisk(directory);
    if (failed < files.size()) {
        removeFrom(failed);
        // The files renamed before it stay: a rename cannot be undone (the old files are gone).
        std::string replaced;
        for (size_t i = 0; i < failed; ++i) replaced += (i ? ", " : "") + files[i].path;
        fail(files[failed].path, "",
             "cannot write file (" + std::generic_category().message(error) + ")" +
                 (replaced.empty() ? "" : "; " + replaced + " already replaced"));
    }
}

void removeStaleTemporaries(const std::string& directory,
                            const std::function<bool(const std::string&)>& ours) {
    namespace fs = std::filesystem;
    std::error_code ec;
    for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const size_t tmp = name.rfind(".tmp");
        if (tmp == std::string::npos || tmp == 0 || !ours(name.substr(0, tmp))) continue;
        const std::string digits = name.substr(tmp + 4);
        if (digits.empty() || digits.size() > 9 || digits[0] == '0' ||  // (as getpid() prints)
            !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
            continue;
        std::error_code ignored;  // (another process may remove it first)
        if (!it->is_regular_file(ignored) || it->is_symlink(ignored)) continue;
        const pid_t pid = pid_t(std::stol(digits));
        if (pid <= 0 || pid == ::getpid() || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
        fs::remove(it->path(), ignored);
    }
}

void writeAtomically(const std::string& path,
                     const std::function<void(const std::string&)>& write) {
    writeTogether({{path, write}});
}

void writeStreamTo(const std::string& tmp, const std::string& path, const std::string& format,
                   const std::function<void(std::ofstream&)>& write) {
    errno = 0;
    std::ofstream os(tmp, std::ios::binary);
    if (!os) failWriting(path, errno);
    try {
        write(os);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        if (!os) failWriting(path, errno);
        fail(path, "", "cannot write " + format + " (" + e.what() + ")");
    }
    if (!os) failWriting(path, errno);  // (the failed write's errno)
    errno = 0;
    os.close();
    if (!os) failWriting(path, errno);
}

void writeTextAtomically(const std::string& path, const std::string& text) {
    writeAtomically(path, [&](const std::string& tmp) {
        writeStreamTo(tmp, path, "file", [&](std::ofstream& os) { os << text; });
    });
}

}  // namespace shvol
