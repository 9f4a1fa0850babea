#pragma once
/// \file Reads a scene file (JSON; the format is documented in README.md, "Scene format").
#include <string>
#include <vector>

#include "shvol/io/json_reader.h"
#include "shvol/io/phase_spec.h"  // readPhaseFunction
#include "shvol/render/scene.h"

namespace shvol {

/// The scene file's document after the overrides ("key.path=value", as --set), unvalidated: what
/// loadScene reads, and what checkpoints, sweeps and the stats file identify a render by.
/// `unchanged` (optional) gets the overrides that changed nothing (applyOverride), `original`
/// (optional) the file's document before them, and `removedBy` (optional) the later override
/// that removed each one's value, or −1 (applyOverrides).
Json sceneDocument(const std::string& path, const std::vector<std::string>& overrides = {},
                   std::vector<std::string>* unchanged = nullptr, Json* original = nullptr,
                   std::vector<int>* removedBy = nullptr);

/// Loads and validates a scene. `overrides` are "key.path=value" assignments applied to the JSON
/// before it is read (the --set option). Relative file names are resolved against the scene's
/// directory. Every error is one line naming the file and the JSON path. With `resolved`, every
/// value the loader read is stored there, defaults filled in (the fully resolved scene of the
/// stats file; an absent environment is recorded as the black constant it stands for).
Scene loadScene(const std::string& path, const std::vector<std::string>& overrides = {},
                Json* resolved = nullptr);

/// Builds a scene from an already-parsed document (tests use this); `path` is used for messages
/// and to resolve relative file names.
Scene sceneFromJson(const Json& doc, const std::string& path, Json* resolved = nullptr);

/// Checks a scene document as sceneFromJson reads it, with the same errors, without reading the
/// grids, the sky image and the meshes it names (each must be an existing regular file) or
/// building the surfaces' BVH: cheap enough to check every run of a batch before the first one
/// renders. Phase functions are built (their tables read, their SH fits made). What only a
/// file's contents can show (a corrupt .vdb, a mesh bounding a medium that is not closed) is
/// found when loading. Returns the scene's camera (its image size, say), and in *resolved the
/// document as sceneFromJson resolves it.
Camera checkScene(const Json& doc, const std::string& path, Json* resolved = nullptr);

}  // namespace shvol
