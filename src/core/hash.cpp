#include "shvol/core/hash.h"

#include <cstdio>

namespace shvol {

std::string hexHash(uint64_t h) {
    char b[17];
    std::snprintf(b, sizeof b, "%016llx", (unsigned long long)h);
    return b;
}

}  // namespace shvol
