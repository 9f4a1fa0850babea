// libFuzzer target: the OBJ reader (readObj: our line scan, tinyobjloader, then our own checks,
// behind readMesh). The input is the file's content; an accepted mesh must be what validateMesh
// promises, and closedMeshDefect must run on it.
#include <cstdint>
#include <string>

#include "fuzz_mesh.h"
#include "shvol/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = shvol::fuzz::scratchDir("obj") + "/input.obj";
    shvol::fuzz::writeFile(path, data, size);
    try {
        shvol::fuzz::checkAcceptedMesh(shvol::readObj(path), "readObj");
    } catch (const shvol::Error& e) {  // the expected outcome of bad input
        shvol::fuzz::expected(e);
    }
    return 0;
}
