#pragma once
/// \file Render checkpoints: the film of a render (per-pixel sample sums and counts, film.h) with
/// the identity of the render it belongs to, so that `shvol render --resume` continues exactly
/// that render.
///
/// Binary layout (little-endian, as the machines shvol runs on):
///   "SHVOLCK2" | u32 n | identity (renderIdentity as compact JSON, n bytes) | i32 width |
///   i32 height | u32 flags | u32 count[w·h] | f64 sum[3·w·h] | (flags bit 0: f64 sumSq[3·w·h]) |
///   (flags bit 1: f64 luminanceSumSq[w·h]; since 6 Dec, unknown without) | u64 FNV-1a checksum
///   of all before it.
/// Format 1 ("SHVOLCK1") held one 64-bit hash of the identity, so a mismatch could not say what
/// differed; its files are recognised and refused (the build they name is not this one anyway).
/// Files are written atomically (temporary + rename), so a kill during a write leaves the previous
/// checkpoint intact.
#include <cstdint>
#include <string>
#include <vector>

#include "shvol/io/json_reader.h"
#include "shvol/render/film.h"

namespace shvol {

/// Identity of a render for checkpoints, part by part, so that a mismatch can name what differs:
///   {"scene": {part: hash}, "inputs": {key: hash}, "build": revision}.
/// "scene" holds FNV-1a hashes of the scene document (render passes the scene as the loader read
/// it, scene_resolved, after the overrides and with the defaults written out, so that a value
/// given as its default matches one left out) cut
/// into parts named like the loader's messages ("camera.fov", "media[0].phase"): objects, and
/// arrays of objects, are cut down to three levels, other values are whole parts. render.spp is
/// left out (a checkpoint may be continued to more samples), and so are the names the `file` keys
/// give: "inputs" holds the contents' hashes of the files the scene names (inputFiles: grids,
/// skies, tables, meshes; the scene file itself left out), by the key that names them, so that
/// one file named otherwise (another relative path, an absolute one) is the same render.
/// "build" is the shvol that renders (its git revision).
/// Everything else must match: a resumed render is then an uninterrupted one, bit for bit.
Json renderIdentity(const Json& sceneDoc, const Json& inputFiles, const std::string& build);

/// What differs between the identity a checkpoint was saved with and the current one, as one
/// clause for a message ("" when they match): the scene parts (said to come from `sources`), the
/// input files, the build.
std::string identityDifference(const Json& saved, const Json& current,
                               const std::string& sources = "scene file, --set or --seed");

void writeCheckpoint(const std::string& path, const Film& film, const Json& identity);

/// Reads a checkpoint; errors (missing, truncated, corrupt, of an older format, or written for
/// another render, saying what differs) are one line naming the file.
Film readCheckpoint(const std::string& path, const Json& identity);

}  // namespace shvol
