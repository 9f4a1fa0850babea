#pragma once
/// \file A clean stop on SIGINT, SIGTERM or SIGHUP: the first signal sets a flag that a long job
/// polls (the renderer's RenderOptions::cancel); a second SIGINT or SIGTERM ends the process as
/// the signal would, and still removes the temporaries of writeAtomically, also when it comes
/// while the stopped job writes what it has. A second SIGHUP changes nothing: a closing terminal
/// sends two.
#include <atomic>

namespace shvol {

/// Catches SIGINT, SIGTERM and SIGHUP while at least one guard lives (the renders of `batch
/// --jobs` run side by side), then restores the actions it replaced. The first signal sets
/// interrupted() and, but for SIGHUP, reinstalls for the next signal of its kind the action that
/// was there before: the one that
/// removes writeAtomically's temporaries (installed first, for a signal whose action was the
/// default) or whatever the program had. A signal the process ignores is left ignored, and once
/// interrupted() is set a new guard catches nothing.
class InterruptGuard {
  public:
    InterruptGuard();
    ~InterruptGuard();
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

    /// Set by the first SIGINT, SIGTERM or SIGHUP under a guard; never cleared.
    static const std::atomic<bool>& interrupted();

    /// The exit code of a job the first signal stopped: 128 + its number (130 for SIGINT, 143 for
    /// SIGTERM, 129 for SIGHUP), as a shell reports a process that signal ended; 130 if no signal
    /// has been caught.
    static int stopExitCode();
};

}  // namespace shvol
