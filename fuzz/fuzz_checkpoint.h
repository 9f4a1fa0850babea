#pragma once
// What the checkpoint fuzzer and its seed writer share: the identity of the render the fuzzer
// resumes, and the form of its inputs.
//
// An input is a checkpoint file without its last 8 bytes, the FNV-1a checksum of the rest
// (io/checkpoint.h): the target appends the right checksum itself, so that mutated inputs reach
// the header's and the identity's checks instead of stopping at the checksum.
#include <cstdint>
#include <string>

#include "shvol/core/hash.h"
#include "shvol/io/checkpoint.h"

namespace shvol::fuzz {

/// The identity the fuzzer resumes with: a few scene parts, one input file, a build.
inline Json checkpointIdentity() {
    const Json scene = Json::parse(R"({"camera": {"fov": 40, "resolution": [4, 3]},
                                       "render": {"spp": 8, "seed": 7},
                                       "media": [{"file": "a.vdb", "phase": {"g": 0.6}}]})");
    const Json inputs = Json::parse(R"([{"key": "media[0].file", "fnv1a64": "00ff"}])");
    return renderIdentity(scene, inputs, "fuzz");
}

/// `bytes` with its checksum appended: a checkpoint file.
inline std::string withChecksum(std::string bytes) {
    const uint64_t sum = fnv1a(bytes.data(), bytes.size());
    bytes.append(reinterpret_cast<const char*>(&sum), sizeof sum);
    return bytes;
}

}  // namespace shvol::fuzz
