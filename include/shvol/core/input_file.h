#pragma once
/// \file Checks on an input file before a reader opens it.
#include <cstdint>
#include <string>

namespace shvol {

/// Why the file at path cannot be read as an input: "no such file", "not a regular file" (a
/// device such as /dev/zero or a FIFO would never end, and a directory is no file to read) or
/// "cannot read file (reason)"; empty when it is an existing regular file.
std::string inputFileProblem(const std::string& path);

/// Size in bytes of the regular file at path. shvol::Error naming the file and its
/// inputFileProblem if there is one.
uintmax_t regularFileSize(const std::string& path);

}  // namespace shvol
