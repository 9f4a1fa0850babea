#include "shvol/render/effects.h"

#include "shvol/render/scene.h"

namespace shvol {

Effects Effects::of(const Scene& scene) {
    Effects e;
    e.volumes = !scene.media.empty();
    bool scatters = false;
    for (const auto& m : scene.media) scatters |= m->scatters();
    e.scattering = e.volumes && scatters && scene.settings.maxDepth >= 1;
    e.multipleScattering = e.scattering && scene.settings.maxDepth > 1;
    const Environment& env = scene.environment;
    const bool envBlack = env.isConstant() && env.constantRadiance().maxCoeff() <= 0;
    e.nextEvent = e.scattering && scene.settings.nee && !envBlack;
    e.environmentImage = !env.isConstant();
    return e;
}

std::vector<std::string> Effects::names() const {
    std::vector<std::string> n;
    n.push_back(environmentImage ? "environment-image" : "environment-constant");
    if (volumes) n.push_back(scattering ? "volume-tracking" : "volume-transmittance");
    if (scattering) n.push_back(multipleScattering ? "multiple-scattering" : "single-scattering");
    if (nextEvent)
        n.push_back(environmentImage ? "nee-environment-importance" : "nee-environment-uniform");
    return n;
}

}  // namespace shvol
