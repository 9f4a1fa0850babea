// libFuzzer target: the tabulated phase function CSV reader (readPhaseTableCsv). The input is
// the file's content; an accepted table must give a usable phase function.
#include <cstdint>
#include <string>

#include "fuzz_util.h"
#include "shvol/core/error.h"
#include "shvol/phase/phase_table_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = shvol::fuzz::scratchDir("phase_csv") + "/input.csv";
    shvol::fuzz::writeFile(path, data, size);
    try {
        shvol::fuzz::checkPhase(shvol::PhaseFunction(shvol::readPhaseTableCsv(path)));
    } catch (const shvol::Error& e) {  // the expected outcome of bad input
        shvol::fuzz::expected(e);
    }
    return 0;
}
