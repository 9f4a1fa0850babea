#include "shvol/core/progress.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

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

std::string progressLine(const std::string& label, double frac, double elapsed, bool final,
                         int columns) {
    frac = std::clamp(frac, 0.0, 1.0);
    char tail[64];
    if (final)
        std::snprintf(tail, sizeof tail, " 100%% %.1fs", elapsed);
    else
        std::snprintf(tail, sizeof tail, " %3d%% ETA %.0fs", int(100 * frac),
                      frac > 0 ? elapsed * (1 - frac) / frac : 0.0);
    // Keep one column free: a line that fills the last column wraps on some terminals.
    const int room = columns - 1 - int(label.size()) - int(std::strlen(tail)) - 3;
    std::string line = label;
    if (room >= 4) {
        const int width = std::min(30, room), filled = int(frac * width);
        std::string bar(filled, '=');
        bar.resize(width, ' ');
        line += " [" + bar + "]";
    }
    line += tail;
    if (int(line.size()) > columns - 1) line.resize(std::max(0, columns - 1));
    return line;
}

void Progress::print(long long d, bool final) {
    const double frac = std::min(1.0, double(d) / double(total_));
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    winsize ws{};
    const int columns =
        ::ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0 ? ws.ws_col : 80;
    const std::string line = progressLine(label_, frac, elapsed, final, columns);
    // Pad with spaces to erase a longer previous line, within the terminal's width.
    const int pad = std::max(0, std::min(columns - 1, lastLength_) - int(line.size()));
    std::fprintf(stderr, "\r%s%*s%s", line.c_str(), pad, "", final ? "\n" : "");
    lastLength_ = int(line.size());
    std::fflush(stderr);
}

}  // namespace shvol
