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

/// What a file whose text begins with `start` is, by its magic number, among the binary files
/// shvol reads: "an OpenVDB grid", "an OpenEXR image" or "a PLY mesh" (ASCII PLY too: its
/// header is no table or JSON); nullptr for anything else. For a file of one of these kinds given
/// where text is read (a scene, a phase table), which the text's reader named by a NUL byte or a
/// row of 1 column (helpers 122, 127).
const char* fileKindByMagic(const std::string& start);

}  // namespace shvol
