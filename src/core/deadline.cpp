#include "shvol/core/deadline.h"

#include <cmath>

namespace shvol {

Deadline::Deadline(std::chrono::steady_clock::time_point start, double seconds) {
    if (!(seconds > 0) || !std::isfinite(seconds)) return;
    // (Beyond about 292 years the nanosecond count of the time point would overflow.)
    const auto limit = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>(std::fmin(seconds, 1e9)));
    watch_ = std::thread([this, limit] {
        std::unique_lock<std::mutex> lock(mutex_);
        if (!wake_.wait_until(lock, limit, [this] { return ended_; }))
            passed_.store(true, std::memory_order_relaxed);
    });
}

Deadline::~Deadline() {
    if (!watch_.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        ended_ = true;
    }
    wake_.notify_one();
    watch_.join();
}

}  // namespace shvol
