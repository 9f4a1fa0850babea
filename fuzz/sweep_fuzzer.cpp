// libFuzzer target: sweep files of `shvol batch` (readSweep), then what a batch checks before it
// renders: the scene document of the first runs (checkScene) and the fingerprints of the files
// they name (fingerprintInputs). Never renders.
//
// Input: the sweep JSON. It is written to a scratch folder that also holds two scenes,
// scene.json (tests/fuzz/scene/homogeneous.json) and cloud.json (vdb_cloud.json), and the files
// they name (tiny.vdb, sky.exr, phase.csv), and ref.exr, so that relative names can load small
// valid files. A sweep may expand to at most kRuns runs here (10^6 in shvol): a few bytes of
// axes can name a million runs, and expanding those under the sanitizers would take minutes.
//
// An accepted sweep must have between 1 and kRuns runs, numbered in order with distinct ids,
// each with a seed in its scene, and a rendered reference must have a seed no run has.
#include <cstdint>
#include <map>
#include <set>
#include <string>

#include "fuzz_util.h"
#include "shvol/core/error.h"
#include "shvol/io/scene_loader.h"
#include "shvol/io/sweep.h"

namespace {

constexpr double kRuns = 1000;
/// Scenes checked per input: an SH fit at a high order takes seconds under the sanitizers.
constexpr size_t kCheckedScenes = 4;

/// The render.seed a run's (or the reference's) scene document holds; bug() if it has none.
double seedOf(const shvol::Json& doc) {
    const auto render = doc.find("render");
    if (render == doc.end() || !render->is_object() || !render->contains("seed") ||
        !(*render)["seed"].is_number())
        shvol::fuzz::bug("an accepted sweep has a run or reference without a numeric seed");
    return (*render)["seed"].get<double>();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string& dir =
        shvol::fuzz::scratchDir("sweep", {{"scene/homogeneous.json", "scene.json"},
                                          {"scene/vdb_cloud.json", "cloud.json"},
                                          {"vdb/sphere8.vdb", "tiny.vdb"},
                                          {"exr/rgb_float.exr", "sky.exr"},
                                          {"exr/rgb_float.exr", "ref.exr"},
                                          {"phase_csv/hg.csv", "phase.csv"}});
    const std::string path = dir + "/sweep.json";
    shvol::fuzz::writeFile(path, data, size);
    try {
        shvol::Sweep s = shvol::readSweep(path, kRuns);
        if (s.runs.empty() || double(s.runs.size()) > kRuns)
            shvol::fuzz::bug("an accepted sweep has no runs or more than it may");
        std::set<std::string> ids;
        std::set<double> seeds;
        std::set<std::string> checked;  // the scene documents checked, as text
        for (size_t i = 0; i < s.runs.size(); ++i) {
            const shvol::SweepRun& run = s.runs[i];
            if (run.index != int(i) || !ids.insert(run.id).second)
                shvol::fuzz::bug("an accepted sweep's runs are out of order or share an id");
            const shvol::Json doc = shvol::runDocument(s.sceneDoc, s.scene, run.sets);
            seeds.insert(seedOf(doc));
            if (checked.size() < kCheckedScenes && checked.insert(shvol::dumpJson(doc)).second)
                shvol::checkScene(doc, s.scene);
        }
        if (s.reference && s.reference->render &&
            seeds.count(seedOf(shvol::runDocument(s.sceneDoc, s.scene, s.reference->sets))))
            shvol::fuzz::bug("a rendered reference has the seed of a run");
        std::map<std::string, shvol::Json> memo;
        shvol::fingerprintInputs(s, memo);
    } catch (const shvol::Error& e) {  // bad input, or a run's scene the batch would refuse
        shvol::fuzz::expected(e);
    }
    return 0;
}
