#pragma once
/// \file A time limit that costs a relaxed atomic load to poll: a thread of its own sleeps until
/// the limit and then sets a flag. (The renderer read the clock before every sample, which cost
/// 12% of the paths of media/plume.json, about 23 ns each, in any render with --time-limit.)
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace shvol {

class Deadline {
  public:
    /// Passes `seconds` after `start`; seconds ≤ 0 or not finite: never (no thread is started).
    Deadline(std::chrono::steady_clock::time_point start, double seconds);
    /// Wakes and joins the thread (at once, if the limit has not come).
    ~Deadline();
    Deadline(const Deadline&) = delete;
    Deadline& operator=(const Deadline&) = delete;

    /// Whether the limit has come (set at most a scheduler's wake-up after it).
    bool passed() const { return passed_.load(std::memory_order_relaxed); }

  private:
    std::atomic<bool> passed_{false};
    std::mutex mutex_;
    std::condition_variable wake_;
    bool ended_ = false;  ///< the destructor's request to stop waiting (under mutex_)
    std::thread watch_;
};

}  // namespace shvol
