// Number checks for command-line options: one line that names the real range.
#include <cmath>
#include <cstdlib>

#include "commands.h"

namespace shvol::app {

CLI::Validator numberIn(double lo, double hi, bool loOpen, const std::string& unit) {
    const std::string range = std::string(loOpen ? "(" : "[") + CLI::detail::to_string(lo) + ", " +
                              CLI::detail::to_string(hi) + "]" + unit;
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            double v = 0;
            if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v))
                return "expected a number, got \"" + text + "\"";
            if (v < lo || v > hi || (loOpen && v <= lo))
                return "must be in " + range + ", got " + text;
            return {};
        },
        "in " + range);
}

CLI::Validator integerIn(long long lo, long long hi) {
    const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            errno = 0;
            char* end = nullptr;
            const long long v = std::strtoll(text.c_str(), &end, 10);
            if (text.empty() || *end != '\0' || errno == ERANGE)
                return "expected an integer in " + range + ", got \"" + text + "\"";
            if (v < lo || v > hi) return "must be an integer in " + range + ", got " + text;
            return {};
        },
        "integer in " + range);
}

}  // namespace shvol::app
