#include "shvol/core/error.h"

#include <cstdio>

namespace shvol {

std::string escapeControlCharacters(const std::string& text) {
    std::string line;
    for (const char c : text) {
        if (static_cast<unsigned char>(c) >= 0x20 && c != 0x7f) {
            line += c;
            continue;
        }
        char escaped[8];
        std::snprintf(escaped, sizeof escaped, "\\u%04x", unsigned(static_cast<unsigned char>(c)));
        line += escaped;
    }
    return line;
}

std::string errorLine(const std::string& file, const std::string& place, const std::string& msg) {
    std::string s;
    if (!file.empty()) s += file + ": ";
    if (!place.empty()) s += place + ": ";
    // Control characters (from a key, a value or a file name) escaped: a NUL would end the line
    // where what() is read as a C string, a newline would break it in two.
    return escapeControlCharacters(s + msg);
}

}  // namespace shvol
