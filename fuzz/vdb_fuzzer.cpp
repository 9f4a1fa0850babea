// libFuzzer target: the VDB loader (loadVdbMedium: reads the grid "density" and builds its
// majorant grid). The input is the file's content; an accepted grid must give finite σ_t and
// majorants with σ_t ≤ majorant at a few points.
#include <cstdint>
#include <string>

#include "fuzz_util.h"
#include "shvol/core/error.h"
#include "shvol/io/vdb.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = shvol::fuzz::scratchDir("vdb") + "/input.vdb";
    shvol::fuzz::writeFile(path, data, size);
    try {
        shvol::VdbMediumDesc desc;
        desc.file = path;
        const auto medium = shvol::loadVdbMedium(desc);
        for (double x : {-0.4, 0.0, 0.13, 0.5}) {
            const shvol::Vec3 p(x, 0.5 * x, -x);
            const double s = medium->sigmaT(p), m = medium->sigmaMajorant(p);
            if (!(std::isfinite(s) && s >= 0 && std::isfinite(m) && s <= m))
                shvol::fuzz::bug("loaded VDB medium has a bad density or majorant");
        }
    } catch (const shvol::Error& e) {  // the expected outcome of bad input
        shvol::fuzz::expected(e);
    }
    return 0;
}
