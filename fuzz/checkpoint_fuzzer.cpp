// libFuzzer target: the checkpoint reader (readCheckpoint) and the identity comparison behind
// its mismatch message. The input is a checkpoint without its checksum (fuzz_checkpoint.h). An
// accepted checkpoint must hold finite sums and non-negative finite sums of squares (of the
// luminances too, where it has them), and must read back unchanged after writeCheckpoint writes it
// again (the writer and the reader agree).
#include <cmath>
#include <cstdint>
#include <string>

#include "fuzz_checkpoint.h"
#include "fuzz_util.h"
#include "shvol/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const shvol::Json identity = shvol::fuzz::checkpointIdentity();
    const std::string& dir = shvol::fuzz::scratchDir("checkpoint");
    const std::string path = dir + "/input.ckpt";
    const std::string bytes =
        shvol::fuzz::withChecksum(std::string(reinterpret_cast<const char*>(data), size));
    shvol::fuzz::writeFile(path, reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    shvol::Film film;
    try {
        film = shvol::readCheckpoint(path, identity);
    } catch (const shvol::Error& e) {  // the expected outcome of bad input
        shvol::fuzz::expected(e);
        return 0;
    }
    for (double s : film.sum)
        if (!std::isfinite(s)) shvol::fuzz::bug("an accepted checkpoint has a sum not finite");
    for (double s : film.sumSq)
        if (!(std::isfinite(s) && s >= 0))
            shvol::fuzz::bug("an accepted checkpoint has a negative or non-finite sum of squares");
    for (double s : film.luminanceSumSq)
        if (!(std::isfinite(s) && s >= 0))
            shvol::fuzz::bug(
                "an accepted checkpoint has a negative or non-finite sum of squared luminances");
    if (!film.luminanceSumSq.empty() && film.luminanceSumSq.size() != film.pixels())
        shvol::fuzz::bug("an accepted checkpoint's squared luminances do not fit its pixels");
    const std::string again = dir + "/again.ckpt";
    shvol::writeCheckpoint(again, film, identity);
    const shvol::Film reread = shvol::readCheckpoint(again, identity);
    if (reread.width != film.width || reread.height != film.height || reread.count != film.count ||
        reread.sum != film.sum || reread.sumSq != film.sumSq ||
        reread.luminanceSumSq != film.luminanceSumSq)
        shvol::fuzz::bug("a checkpoint written again does not read back as it was");
    return 0;
}
