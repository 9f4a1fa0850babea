#pragma once
/// \file Where a render came from, for its stats file: the input files with sizes and content
/// hashes, the command line and the machine.
#include <map>
#include <string>
#include <vector>

#include "shvol/io/json_reader.h"

namespace shvol {

/// Every string value of a key named "file" in the scene document (sceneDocument, after the
/// overrides: the scene's inputs — grids, environment maps, phase tables), plus the scene file:
///   [{"key": "media[0].file", "path": "/abs/cloud.vdb", "bytes": 123, "fnv1a64": "…"}, …]
/// Relative paths are resolved against the scene's directory as the loader does. With `memo`, a
/// file already in it (by path) is not read again, and each one read is added: a sweep whose runs
/// name the same grid reads it once.
Json inputFiles(const Json& sceneDoc, const std::string& scenePath,
                std::map<std::string, Json>* memo = nullptr);

/// The contents of the files a scene names, from its inputFiles (the scene file itself left out),
/// one line "key fnv1a64" each: for identities that must change when an input file does.
std::string namedFileContents(const Json& inputFiles);

/// Size and FNV-1a hash of a file's contents ({"bytes", "fnv1a64"}); shvol::Error if unreadable.
Json fileFingerprint(const std::string& path);

/// This process's command line (/proc/self/cmdline), arguments with spaces or quotes quoted.
std::string commandLine();

/// {"cpu": model name, "hardware_threads": n, "os": "Linux 6.1.0 x86_64", "host": name}
Json machineDescription();

}  // namespace shvol
