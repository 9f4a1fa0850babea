#pragma once
// Helpers shared by the libFuzzer targets in this folder (README, "Fuzzing and sanitizers").
//
// Every target feeds one input to one loader and treats a shvol::Error as the expected outcome of
// bad input; any other exception escapes and libFuzzer reports it as a crash, as it does for
// AddressSanitizer and UndefinedBehaviorSanitizer findings, leaks, timeouts and huge allocations.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "shvol/phase/phase_function.h"

namespace shvol::fuzz {

/// A directory private to this process (/tmp/shvol_fuzz_<target>_<pid>), created on first use,
/// holding copies of `seeds` (pairs of a file name in tests/fuzz/ and the name to copy it to, so
/// that inputs can refer to small valid files), and removed when the process exits normally.
inline const std::string& scratchDir(
    const char* target, std::initializer_list<std::pair<const char*, const char*>> seeds = {}) {
    namespace fs = std::filesystem;
    // Never destroyed, so that the exit handler below can still read it.
    static const std::string* dir = [&] {
        const fs::path d = fs::temp_directory_path() /
                           ("shvol_fuzz_" + std::string(target) + "_" + std::to_string(::getpid()));
        fs::create_directories(d);
        for (const auto& [from, to] : seeds)
            fs::copy_file(fs::path(SHVOL_FUZZ_CORPUS_DIR) / from, d / to,
                          fs::copy_options::overwrite_existing);
        return new std::string(d.string());
    }();
    static const bool cleanup = std::atexit([] {
                                    std::error_code ec;
                                    fs::remove_all(*dir, ec);
                                }) == 0;
    (void)cleanup;
    return *dir;
}

/// Writes the bytes to `path` (overwriting it).
inline void writeFile(const std::string& path, const uint8_t* data, size_t size) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

/// Called with the shvol::Error that bad input is expected to raise: prints it when the
/// environment variable SHVOL_FUZZ_VERBOSE is set (to see why seeds or crash inputs are refused).
inline void expected(const std::exception& e) {
    static const bool verbose = std::getenv("SHVOL_FUZZ_VERBOSE") != nullptr;
    if (verbose) std::fprintf(stderr, "shvol fuzz: refused: %s\n", e.what());
}

/// A finding that is not a crash by itself (e.g. an accepted input that loads as NaN): abort, so
/// that libFuzzer saves the input.
[[noreturn]] inline void bug(const char* what) {
    std::fprintf(stderr, "shvol fuzz: %s\n", what);
    std::abort();
}

/// An accepted phase function must be usable: finite, non-negative values, and samples with a
/// finite positive pdf, for a few fixed directions.
inline void checkPhase(const PhaseFunction& p) {
    const Vec3 wo(0, 0, 1);
    for (double z : {1.0, 0.5, 0.0, -0.3, -1.0}) {
        const Vec3 wi(std::sqrt(std::max(0.0, 1 - z * z)), 0, z);
        const double v = p.eval(wo, wi), pdf = p.pdf(wo, wi);
        if (!(std::isfinite(v) && v >= 0)) bug("phase function value is negative or not finite");
        if (!(std::isfinite(pdf) && pdf >= 0)) bug("phase pdf is negative or not finite");
    }
    for (double u : {0.01, 0.25, 0.5, 0.99}) {
        const PhaseSample s = p.sample(wo, Vec2(u, 0.3));
        if (!s.wi.allFinite() || !(s.pdf > 0) || !std::isfinite(s.pdf) || !std::isfinite(s.value))
            bug("phase sample is not finite or has pdf 0");
    }
}

}  // namespace shvol::fuzz
