#pragma once
/// \file Checks on an input file before a reader opens it.
#include <cstdint>
#include <string>
#include <string_view>

namespace shvol {

/// Why the file at path cannot be read as an input: "no such file", "not a regular file" (a
/// device such as /dev/zero or a FIFO would never end, and a directory is no file to read) or
/// "cannot read file (reason)"; empty when it is an existing regular file.
std::string inputFileProblem(const std::string& path);

/// Size in bytes of the regular file at path. shvol::Error naming the file and its
/// inputFileProblem if there is one.
uintmax_t regularFileSize(const std::string& path);

/// The length of the UTF-8 byte-order mark that `text` starts with (a Windows editor's; no part of
/// a text file's first line): 3, or 0 without one.
inline size_t utf8BomLength(std::string_view text) {
    return text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
}

/// The kind of a file that starts with `start`, told by its magic number: "an OpenVDB grid", "an
/// OpenEXR image", "a PLY mesh" (ASCII PLY too), the files shvol reads that are not JSON or CSV,
/// or "a PNG image" (which `tonemap` writes);
/// nullptr for any other start. Readers of JSON and CSV name such a file by its kind, where their
/// own errors ("a NUL byte", "expected 2 columns") said nothing of it (helpers 122, 127).
const char* fileKindByMagic(const std::string& start);
/// fileKindByMagic's kind, or "JSON text" for a start whose first character but blanks opens an
/// object or an array: for readers of binary files (images, checkpoints), which name a file of
/// another kind as such (helper 139: a stats file given to `diff`).
const char* fileKindOfStart(const std::string& start);
/// fileKindOfStart of the file at path's first 256 bytes (nullptr if it cannot be read).
const char* fileKindOfFile(const std::string& path);
/// "the file is K, not WANTED" where the file at path is of a known kind K (fileKindOfFile) other
/// than `wanted` ("an OpenEXR image"), else "": the message of a reader that failed on a file of
/// another kind (EXR, VDB and checkpoint readers).
std::string fileOfAnotherKind(const std::string& path, const std::string& wanted);

}  // namespace shvol
