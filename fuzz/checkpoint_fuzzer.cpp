// libFuzzer target: the checkpoint reader (readCheckpoint) and the identity comparison behind
// its mismatch message. The input is a checkpoint without its checksum (fuzz_checkpoint.h); an
// accepted checkpoint must give a film whose buffers match its resolution.
#include <cstdint>
#include <string>

#include "fuzz_checkpoint.h"
#include "fuzz_util.h"
#include "shvol/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const shvol::Json identity = shvol::fuzz::checkpointIdentity();
    const std::string path = shvol::fuzz::scratchDir("checkpoint") + "/input.ckpt";
    const std::string bytes =
        shvol::fuzz::withChecksum(std::string(reinterpret_cast<const char*>(data), size));
    shvol::fuzz::writeFile(path, reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    try {
        const shvol::Film film = shvol::readCheckpoint(path, identity);
        const size_t pixels = size_t(film.width) * size_t(film.height);
        if (film.width <= 0 || film.height <= 0 || film.count.size() != pixels ||
            film.sum.size() != 3 * pixels ||
            (!film.sumSq.empty() && film.sumSq.size() != 3 * pixels))
            shvol::fuzz::bug("an accepted checkpoint's film does not match its resolution");
    } catch (const shvol::Error& e) {  // the expected outcome of bad input
        shvol::fuzz::expected(e);
    }
    return 0;
}
