#pragma once
// Helpers shared by the test programs.
#include <functional>
#include <string>

#include "shvol/core/error.h"

namespace shvol::test {

/// The message of the shvol::Error that f throws, or "(no error)".
inline std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace shvol::test
