#include "shvol/core/progress.h"

#include <unistd.h>

#include <cstdio>

namespace shvol {

Progress::Progress(std::string label, long long total, bool enabled)
    : label_(std::move(label)), total_(std::max(1LL, total)), enabled_(enabled) {
    start_ = lastPrint_ = std::chrono::steady_clock::now();
}

Progress::~Progress() {
    done();
}

bool Progress::stderrIsTerminal() {
    return ::isatty(STDERR_FILENO) == 1;
}

void Progress::advance(long long n) {
    const long long d = done_ += n;
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() || now - lastPrint_ < std::chrono::milliseconds(200)) return;
    lastPrint_ = now;
    print(d, false);
}

void Progress::done() {
    if (!enabled_ || finished_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    finished_ = true;
    print(done_, true);
}

void Progress::print(long long d, bool final) {
    const double frac = std::min(1.0, double(d) / double(total_));
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const int width = 30, filled = int(frac * width);
    std::string bar(filled, '=');
    bar.resize(width, ' ');
    if (final)
        std::fprintf(stderr, "\r%s [%s] 100%% %.1fs      \n", label_.c_str(), bar.c_str(), elapsed);
    else {
        const double eta = frac > 0 ? elapsed * (1 - frac) / frac : 0;
        std::fprintf(stderr, "\r%s [%s] %3d%% ETA %.0fs   ", label_.c_str(), bar.c_str(),
                     int(100 * frac), eta);
    }
    std::fflush(stderr);
}

}  // namespace shvol
