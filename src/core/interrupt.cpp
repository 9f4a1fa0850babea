#include "shvol/core/interrupt.h"

#include <signal.h>

#include <csignal>
#include <mutex>

#include "shvol/core/atomic_file.h"

namespace shvol {

namespace {

using Handler = void (*)(int);

std::atomic<bool> gInterrupted{false};
/// The handlers the guards replaced, read by the signal handler (lock-free atomics).
std::atomic<Handler> gPreviousInt{SIG_DFL}, gPreviousTerm{SIG_DFL};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<Handler>::is_always_lock_free,
              "the signal handler reads these");

extern "C" void onInterrupt(int sig) {
    gInterrupted.store(true);
    std::signal(sig, (sig == SIGINT ? gPreviousInt : gPreviousTerm).load());
}

std::mutex gMutex;
int gDepth = 0;

}  // namespace

InterruptGuard::InterruptGuard() {
    const std::lock_guard<std::mutex> lock(gMutex);
    if (gDepth++ > 0) return;
    // Installed before this guard's own, so that they are what the first signal hands back to
    // (installed later, they would see this guard's handler and stay away from SIGINT and
    // SIGTERM for good).
    removeTemporariesOnSignals();
    // The previous handler is stored before ours is in place: a signal right after it must
    // find it.
    for (const int sig : {SIGINT, SIGTERM}) {
        struct sigaction old {};
        ::sigaction(sig, nullptr, &old);
        (sig == SIGINT ? gPreviousInt : gPreviousTerm).store(old.sa_handler);
        std::signal(sig, onInterrupt);
    }
}

InterruptGuard::~InterruptGuard() {
    const std::lock_guard<std::mutex> lock(gMutex);
    if (--gDepth > 0) return;
    std::signal(SIGINT, gPreviousInt.load());
    std::signal(SIGTERM, gPreviousTerm.load());
}

const std::atomic<bool>& InterruptGuard::interrupted() {
    return gInterrupted;
}

}  // namespace shvol
