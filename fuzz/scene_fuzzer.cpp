// libFuzzer target: the scene loader with --set overrides (loadScene). Only loads, never renders.
//
// Input: the scene JSON, then any number of overrides, each introduced by a line starting with
// "--set " (as on the command line, "--set key.path=value"):
//     {"camera": {"resolution": [8, 8]}, "media": [{"file": "tiny.vdb"}]}
//     --set media.0.density_scale=3
//     --set render.spp=2
// The scene is written to a scratch folder that also holds tiny.vdb (tests/fuzz/vdb/sphere8.vdb),
// sky.exr (tests/fuzz/exr/rgb_float.exr) and phase.csv (tests/fuzz/phase_csv/hg.csv), so that
// relative file names in the scene can load small valid files.
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_util.h"
#include "shvol/core/error.h"
#include "shvol/io/scene_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string& dir = shvol::fuzz::scratchDir("scene", {{"vdb/sphere8.vdb", "tiny.vdb"},
                                                               {"exr/rgb_float.exr", "sky.exr"},
                                                               {"phase_csv/hg.csv", "phase.csv"}});
    const std::string input(reinterpret_cast<const char*>(data), size);
    const std::string marker = "\n--set ";
    size_t end = input.find(marker);
    const std::string scene = input.substr(0, end);
    std::vector<std::string> overrides;
    while (end != std::string::npos) {
        const size_t begin = end + marker.size();
        end = input.find(marker, begin);
        std::string o = input.substr(begin, end == std::string::npos ? end : end - begin);
        if (!o.empty() && o.back() == '\n') o.pop_back();  // the input's final newline
        overrides.push_back(o);
    }
    const std::string path = dir + "/scene.json";
    shvol::fuzz::writeFile(path, reinterpret_cast<const uint8_t*>(scene.data()), scene.size());
    try {
        const shvol::Scene s = shvol::loadScene(path, overrides);
        for (const auto& m : s.media) shvol::fuzz::checkPhase(m->phase());
    } catch (const shvol::Error& e) {  // the expected outcome of bad input
        shvol::fuzz::expected(e);
    }
    return 0;
}
