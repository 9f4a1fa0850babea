#include "shvol/core/error.h"

#include <cstdio>

namespace shvol {

namespace {
/// The length of the well-formed UTF-8 sequence at text[i] (RFC 3629: no overlong forms, no
/// surrogates, nothing above U+10FFFF), or 0.
size_t utf8Length(const std::string& text, size_t i) {
    const auto at = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char c = at(i);
    size_t n = 0;
    unsigned char lo = 0x80, hi = 0xbf;  // the second byte's range
    if (c >= 0xc2 && c <= 0xdf)
        n = 2;
    else if (c >= 0xe0 && c <= 0xef)
        n = 3, lo = c == 0xe0 ? 0xa0 : 0x80, hi = c == 0xed ? 0x9f : 0xbf;
    else if (c >= 0xf0 && c <= 0xf4)
        n = 4, lo = c == 0xf0 ? 0x90 : 0x80, hi = c == 0xf4 ? 0x8f : 0xbf;
    if (n == 0 || i + n > text.size() || at(i + 1) < lo || at(i + 1) > hi) return 0;
    for (size_t k = 2; k < n; ++k)
        if (at(i + k) < 0x80 || at(i + k) > 0xbf) return 0;
    return n;
}
}  // namespace

std::string escapeControlCharacters(const std::string& text) {
    std::string line;
    for (size_t i = 0; i < text.size();) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        char escaped[8];
        if (c >= 0x80) {
            if (const size_t n = utf8Length(text, i)) {
                line.append(text, i, n);
                i += n;
                continue;
            }
            std::snprintf(escaped, sizeof escaped, "\\x%02x", unsigned(c));  // not UTF-8
        } else if (c >= 0x20 && c != 0x7f) {
            line += char(c), ++i;
            continue;
        } else {
            std::snprintf(escaped, sizeof escaped, "\\u%04x", unsigned(c));
        }
        line += escaped, ++i;
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
