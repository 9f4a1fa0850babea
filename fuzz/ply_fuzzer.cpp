// libFuzzer target: the PLY reader (parsePly, behind readPly and readMesh). The input is the
// file's content; an accepted mesh must be what validateMesh promises, and closedMeshDefect must
// run on it.
#include <cstdint>
#include <string_view>

#include "fuzz_mesh.h"
#include "shvol/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        shvol::fuzz::checkAcceptedMesh(
            shvol::parsePly(std::string_view(reinterpret_cast<const char*>(data), size),
                            "input.ply"),
            "parsePly");
    } catch (const shvol::Error& e) {  // the expected outcome of bad input
        shvol::fuzz::expected(e);
    }
    return 0;
}
