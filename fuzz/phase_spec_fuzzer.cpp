// libFuzzer target: the phase spec parser (parsePhaseSpec: short form or JSON object, the
// `shvol phase` SPEC argument and a scene's "phase" object). The input is the spec; relative
// table files resolve against a scratch folder holding phase.csv (tests/fuzz/phase_csv/hg.csv).
#include <cstdint>
#include <string>

#include "fuzz_util.h"
#include "shvol/core/error.h"
#include "shvol/io/phase_spec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string& dir =
        shvol::fuzz::scratchDir("phase_spec", {{"phase_csv/hg.csv", "phase.csv"}});
    const std::string spec(reinterpret_cast<const char*>(data), size);
    try {
        shvol::fuzz::checkPhase(shvol::parsePhaseSpec(spec, dir));
    } catch (const shvol::Error& e) {  // the expected outcome of bad input
        shvol::fuzz::expected(e);
    }
    return 0;
}
