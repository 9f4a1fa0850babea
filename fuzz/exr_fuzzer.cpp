// libFuzzer target: the EXR loader (readExr, used for environment maps and by `shvol diff` and
// `shvol tonemap`). The input is the file's content.
#include <cstdint>
#include <string>

#include "fuzz_util.h"
#include "shvol/core/error.h"
#include "shvol/io/exr.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = shvol::fuzz::scratchDir("exr") + "/input.exr";
    shvol::fuzz::writeFile(path, data, size);
    try {
        const shvol::Image img = shvol::readExr(path);
        if (img.width < 1 || img.height < 1 || img.rgb.size() != size_t(3) * img.width * img.height)
            shvol::fuzz::bug("readExr returned an inconsistent image");
        for (float v : img.rgb)
            if (!(std::isfinite(v) && v >= 0)) shvol::fuzz::bug("readExr accepted a bad pixel");
    } catch (const shvol::Error& e) {  // the expected outcome of bad input
        shvol::fuzz::expected(e);
    }
    return 0;
}
