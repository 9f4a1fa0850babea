#include "shvol/core/error.h"

namespace shvol {

std::string errorLine(const std::string& file, const std::string& place, const std::string& msg) {
    std::string s;
    if (!file.empty()) s += file + ": ";
    if (!place.empty()) s += place + ": ";
    return s + msg;
}

}  // namespace shvol
