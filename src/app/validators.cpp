// Checks for command-line options: numbers in one line that names the real range, file extensions,
// outputs that would replace an input.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "commands.h"
#include "shvol/core/atomic_file.h"

namespace shvol::app {

namespace {
/// Leading blanks, which strtoll and CLI11's number parsing skip (trailing ones they refuse):
/// refused too, so that " 4" and "4 " get the same answer.
bool startsBlank(const std::string& text) {
    return !text.empty() && std::isspace(static_cast<unsigned char>(text.front()));
}
}  // namespace

CLI::Validator numberIn(double lo, double hi, bool loOpen, const std::string& unit) {
    const std::string range = std::string(loOpen ? "(" : "[") + CLI::detail::to_string(lo) + ", " +
                              CLI::detail::to_string(hi) + "]" + unit;
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            double v = 0;
            // (Decimal only, as whole-number options and phase specifications take them: 0x10
            // was read as 16; helper 130.)
            if (startsBlank(text) || text.find_first_of("xX") != std::string::npos ||
                !CLI::detail::lexical_cast(text, v) ||
                (!std::isfinite(v) && text.find_first_of("0123456789") == std::string::npos))
                return "expected a decimal number, got \"" + text + "\"";
            if (!std::isfinite(v))  // (1e400, which is decimal; helper 131)
                return "\"" + text + "\" is beyond the range of a double (±1.8e308)";
            // A number below the smallest double reads as 0, which it is not (1e-400 made
            // --max-rmse 0; helper 130).
            if (v == 0 && text.substr(0, text.find_first_of("eE")).find_first_of("123456789") !=
                              std::string::npos)
                return "\"" + text +
                       "\" is below the smallest double (4.9e-324) and would read as 0";
            if (v < lo || v > hi || (loOpen && v <= lo))
                return "must be in " + range + ", got " + text;
            return {};
        },
        "in " + range);
}

bool hasExtension(const std::string& path, const std::string& ext) {
    if (path.size() < ext.size()) return false;
    std::string tail = path.substr(path.size() - ext.size());
    for (char& ch : tail) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return tail == ext;
}

std::string outputNameProblem(const std::string& path, const std::string& ext,
                              const std::string& what) {
    if (!hasExtension(path, ext)) return what + "; name the file " + ext;
    if (std::filesystem::path(path.substr(0, path.size() - ext.size())).filename().empty())
        return "the output needs a name before " + ext;
    return "";
}

CLI::Option* addSetOption(CLI::App* c, std::vector<std::string>& sets) {
    return c->add_option("--set", sets, "Override a scene value: key.path=value (repeatable)")
        ->expected(1)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->allow_extra_args(false)
        ->default_str("");
}

CLI::Validator notAStrayOverride() {
    return CLI::Validator(
        [](std::string& name) {
            std::error_code ec;
            if (name.find('=') == std::string::npos || std::filesystem::exists(name, ec))
                return std::string();
            return name + ": no such file; " + kOneValuePerSet;
        },
        "");
}

CLI::Validator nonEmptyName() {
    return CLI::Validator(
        [](std::string& name) {
            return name.empty() ? std::string("an empty name") : std::string();
        },
        "");
}

CLI::Validator writableOutput() {
    return CLI::Validator(
        [](std::string& path) {
            const std::string problem = outputFileProblem(path);
            return problem.empty() ? problem : path + ": cannot write: " + problem;
        },
        "FILE");
}

CLI::Validator outputNamed(const std::string& ext, const std::string& what) {
    return CLI::Validator(
        [ext, what](std::string& path) {
            const std::string problem = outputNameProblem(path, ext, what);
            if (problem.empty()) return writableOutput()(path);
            return path.empty() ? problem : path + ": " + problem;
        },
        "FILE" + ext);
}

bool sameFile(const std::string& a, const std::string& b) {
    namespace fs = std::filesystem;
    if (a.empty() || b.empty()) return false;
    std::error_code ec, ea, eb;
    if (fs::equivalent(a, b, ec)) return true;
    // (Made absolute first: weakly_canonical leaves a relative path with no existing prefix,
    // "x.exr", as it is, and "./x.exr" becomes absolute.)
    const auto normal = [](const std::string& p, std::error_code& e) {
        const fs::path abs = fs::absolute(p, e);
        return e ? abs : fs::weakly_canonical(abs, e);
    };
    // Links followed first: a dangling link names the file it would be written to.
    const fs::path pa = normal(linkTarget(a).string(), ea), pb = normal(linkTarget(b).string(), eb);
    return !ea && !eb && pa == pb;
}

CLI::Validator integerIn(long long lo, long long hi) {
    const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            errno = 0;
            char* end = nullptr;
            const long long v = std::strtoll(text.c_str(), &end, 10);
            if (text.empty() || startsBlank(text) || *end != '\0' || errno == ERANGE)
                return "expected an integer in " + range + ", got \"" + text + "\"";
            if (v < lo || v > hi) return "must be an integer in " + range + ", got " + text;
            // The value checked is the one used: CLI11 converts with base 0, which took "010" for
            // octal 8 (a seed sweep of zero-padded numbers rendered other seeds; helper 152), so
            // the text becomes v's decimal digits (for options given with ->transform).
            text = std::to_string(v);
            return {};
        },
        "integer in " + range);
}

}  // namespace shvol::app
