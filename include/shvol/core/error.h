#pragma once
/// \file Errors that reach the user: one line naming the file and the place in it.
#include <stdexcept>
#include <string>

namespace shvol {

/// A user-facing error. what() is the whole line printed by the command-line program, in the
/// form "FILE: PLACE: message" (PLACE is a JSON path such as media[0].phase.g, or a grid name).
class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Builds "file: place: message", leaving out empty parts, with control characters escaped
/// (escapeControlCharacters), so that the line stays one whole line.
std::string errorLine(const std::string& file, const std::string& place, const std::string& msg);

/// `text` with its control characters (below U+0020, and DEL) written as JSON writes them:
/// \u0000, \u000a, and each byte that is not part of well-formed UTF-8 as \xff (a grid name read
/// from a damaged file); the rest, UTF-8 included, unchanged.
std::string escapeControlCharacters(const std::string& text);

[[noreturn]] inline void fail(const std::string& file, const std::string& place,
                              const std::string& msg) {
    throw Error(errorLine(file, place, msg));
}

/// An error in command-line option `option` found when a command runs rather than as the options
/// are read: "OPTION: message (see --help)", the form of the option errors the parser reports.
[[noreturn]] inline void failOption(const std::string& option, const std::string& msg) {
    fail("", option, msg + " (see --help)");
}

}  // namespace shvol
