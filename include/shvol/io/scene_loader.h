#pragma once
/// \file Reads a scene file (JSON; the format is documented in README.md, "Scene format").
#include <string>
#include <vector>

#include "shvol/io/json_reader.h"
#include "shvol/io/phase_spec.h"  // readPhaseFunction
#include "shvol/render/scene.h"

namespace shvol {

/// Loads and validates a scene. `overrides` are "key.path=value" assignments applied to the JSON
/// before it is read (the --set option). Relative file names are resolved against the scene's
/// directory. Every error is one line naming the file and the JSON path.
Scene loadScene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Builds a scene from an already-parsed document (tests use this); `path` is used for messages
/// and to resolve relative file names.
Scene sceneFromJson(const Json& doc, const std::string& path);

}  // namespace shvol
