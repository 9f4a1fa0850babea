#pragma once
/// \file Checks on an input file before a reader opens it.
#include <cstdint>
#include <string>

namespace shvol {

/// Size in bytes of the regular file at path. shvol::Error naming the file if it is missing,
/// unreadable or not a regular file (a device such as /dev/zero or a FIFO would never end, and a
/// directory is no file to read).
uintmax_t regularFileSize(const std::string& path);

}  // namespace shvol
