#include "shvol/core/interrupt.h"

#include <signal.h>

#include <mutex>

#include "shvol/core/atomic_file.h"

namespace shvol {

namespace {

/// SIGHUP too: a render whose terminal closes saves what it has, as at SIGTERM (it ended with 129
/// and no checkpoint; helper 127).
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
constexpr int kSignalCount = int(sizeof kSignals / sizeof kSignals[0]);

std::atomic<bool> gInterrupted{false};
std::atomic<int> gFirstSignal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free,
              "the signal handler stores to these atomics");

/// The actions the guards replaced, one per entry of kSignals, and whether a guard's handler is
/// installed for it. Written only under gMutex while none of this file's handlers is installed
/// (before installing, after restoring), so the handler reads them without a race.
struct sigaction gPrevious[kSignalCount];
bool gCaught[kSignalCount] = {};

int indexOf(int sig) {
    int i = 0;
    while (kSignals[i] != sig) ++i;  // (only kSignals' handlers are ours)
    return i;
}

/// Sets the flag and puts the previous action back for the next SIGINT or SIGTERM, which ends the
/// process as it would have. SIGHUP stays caught: a closing terminal sends it twice, from the
/// shell and from the kernel as the session ends, and the second ended the render before it had
/// written anything (helper 129).
extern "C" void onInterrupt(int sig) {
    int none = 0;
    gFirstSignal.compare_exchange_strong(none, sig);
    gInterrupted.store(true);
    if (sig != SIGHUP) ::sigaction(sig, &gPrevious[indexOf(sig)], nullptr);
}

std::mutex gMutex;
int gDepth = 0;

}  // namespace

InterruptGuard::InterruptGuard() {
    const std::lock_guard<std::mutex> lock(gMutex);
    // Once interrupted, a later guard (the next render of `batch --jobs`) catches nothing: the
    // next signal ends the process.
    if (gDepth++ > 0 || gInterrupted.load()) return;
    // The temporaries' handlers go in before this guard's, so that they are what the first signal
    // hands back to (installed later, they would find this guard's handler and stay away from
    // SIGINT, SIGTERM and SIGHUP for good).
    removeTemporariesOnSignals();
    for (const int sig : kSignals) {
        const int i = indexOf(sig);
        // The previous action is stored before ours is in place: a signal right after it must
        // find it. A signal the process ignores (started with nohup or in the background of a
        // script) stays ignored.
        if (::sigaction(sig, nullptr, &gPrevious[i]) != 0 || gPrevious[i].sa_handler == SIG_IGN)
            continue;
        struct sigaction ours {};
        ours.sa_handler = onInterrupt;
        ours.sa_flags = SA_RESTART;  // as std::signal has it: reads and waits go on
        sigemptyset(&ours.sa_mask);
        gCaught[i] = ::sigaction(sig, &ours, nullptr) == 0;
    }
}

InterruptGuard::~InterruptGuard() {
    const std::lock_guard<std::mutex> lock(gMutex);
    if (--gDepth > 0) return;
    for (const int sig : kSignals) {
        const int i = indexOf(sig);
        if (gCaught[i]) ::sigaction(sig, &gPrevious[i], nullptr);
        gCaught[i] = false;
    }
}

const std::atomic<bool>& InterruptGuard::interrupted() {
    return gInterrupted;
}

int InterruptGuard::stopExitCode() {
    const int sig = gFirstSignal.load();
    return 128 + (sig != 0 ? sig : SIGINT);
}

}  // namespace shvol
