#pragma once
/// \file Everything a render needs, as loaded from a scene file.
#include <memory>
#include <string>
#include <vector>

#include "shvol/lights/environment.h"
#include "shvol/media/medium.h"
#include "shvol/render/camera.h"

namespace shvol {

struct RenderSettings {
    int spp = 16;
    uint64_t seed = 1;
    int maxDepth = 64;  ///< maximum number of scattering events per path (1 = single scattering)
    int rrDepth = 3;    ///< Russian roulette starts after this many scattering events
    bool nee = true;    ///< next-event estimation towards the environment, MIS with phase sampling
    TransmittanceEstimator transmittance = TransmittanceEstimator::Ratio;
};

struct Scene {
    Camera camera;
    RenderSettings settings;
    Environment environment = Environment::constant(Spectrum::Zero(), false);
    std::vector<std::unique_ptr<Medium>> media;
    std::string path;  ///< the scene file, for messages
};

}  // namespace shvol
