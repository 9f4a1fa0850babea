// The text of a failure for shvol's one error line.
#include <new>

#include "commands.h"
#include "shvol/core/error.h"

namespace shvol::app {

std::string errorMessage(const std::exception& e) {
    if (dynamic_cast<const Error*>(&e)) return e.what();
    // (A 16384² render needs about 11 GB for its film and image, say.)
    if (dynamic_cast<const std::bad_alloc*>(&e))
        return "out of memory; outputs not written yet were not written (the stats' "
               "peak_memory_mib of a smaller run shows what the work takes)";
    return std::string("internal error: ") + e.what();
}

std::string errorLine(const std::exception& e) {
    const bool internal =
        !dynamic_cast<const Error*>(&e) && !dynamic_cast<const std::bad_alloc*>(&e);
    return (internal ? "shvol: " : "shvol: error: ") + errorMessage(e);
}

}  // namespace shvol::app
