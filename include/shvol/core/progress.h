#pragma once
/// \file A thread-safe progress bar with ETA on stderr (only when stderr is a terminal).
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace shvol {

/// The text of one progress line (without the leading carriage return) fitted to a terminal of
/// `columns` characters: "label [====    ]  42% ETA 12s", the bar shrinking to fit and left out
/// when there is no room, so that the line never wraps (which would scroll instead of redraw).
std::string progressLine(const std::string& label, double fraction, double elapsedSeconds,
                         bool final, int columns);

class Progress {
  public:
    /// enabled = false prints nothing (e.g. --quiet, or stderr is not a terminal).
    Progress(std::string label, long long total, bool enabled);
    ~Progress();
    void advance(long long n = 1);
    void done();
    /// True when stderr is a terminal.
    static bool stderrIsTerminal();

  private:
    void print(long long done, bool final);
    std::string label_;
    long long total_;
    bool enabled_, finished_ = false;
    int lastLength_ = 0;  ///< length of the last line printed
    std::atomic<long long> done_{0};
    std::mutex mutex_;
    std::chrono::steady_clock::time_point start_, lastPrint_;
};

}  // namespace shvol
