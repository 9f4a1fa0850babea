#include "shvol/core/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>

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

/// SIGTERM, SIGHUP or SIGINT ends the process as it would have, without the temporaries.
extern "C" void removeTemporariesAndDie(int sig) {
    for (TemporarySlot& s : gSlots)
        if (s.armed.load()) ::unlink(s.path);
    std::signal(sig, SIG_DFL);
    std::raise(sig);
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

}  // namespace

std::string outputFileProblem(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path dir = fs::path(path).parent_path();
    if (!dir.empty()) {
        const fs::file_status st = fs::status(dir, ec);
        if (st.type() == fs::file_type::not_found)
            return "directory " + dir.string() + " does not exist";
        if (!ec && !fs::is_directory(st)) return dir.string() + " is not a directory";
    }
    if (fs::is_directory(path, ec)) return "is a directory";
    return "";
}

void failWriting(const std::string& path, int error) {
    fail(path, "",
         error == 0 ? "cannot write file"
                    : std::string("cannot write file (") + std::strerror(error) + ")");
}

void writeAtomically(const std::string& path,
                     const std::function<void(const std::string&)>& write) {
    const std::string tmp = path + ".tmp" + std::to_string(::getpid());
    const TemporaryGuard guard(tmp);
    try {
        write(tmp);
    } catch (...) {
        std::remove(tmp.c_str());
        throw;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int error = errno;
        std::remove(tmp.c_str());
        failWriting(path, error);
    }
}

void writeTextAtomically(const std::string& path, const std::string& text) {
    writeAtomically(path, [&](const std::string& tmp) {
        errno = 0;
        std::ofstream f(tmp, std::ios::binary);
        f << text;
        f.close();
        if (!f) failWriting(path, errno);
    });
}

}  // namespace shvol
