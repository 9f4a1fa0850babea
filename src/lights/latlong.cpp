#include "shvol/lights/latlong.h"

#include "shvol/core/error.h"

namespace shvol {

LatLongMapping latLongMappingFromName(const std::string& name) {
    if (name == "blender") return LatLongMapping::Blender;
    if (name == "shvol") return LatLongMapping::Shvol;
    throw Error("unknown lat-long mapping \"" + name + "\"; expected \"blender\" or \"shvol\"");
}

const char* latLongMappingName(LatLongMapping m) {
    return m == LatLongMapping::Blender ? "blender" : "shvol";
}

}  // namespace shvol
