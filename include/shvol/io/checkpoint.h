#pragma once
/// \file Render checkpoints: the film of a render (per-pixel sample sums and counts, film.h) with
/// the identity of the render it belongs to, so that `shvol render --resume` continues exactly
/// that render.
///
/// Binary layout (little-endian, as the machines shvol runs on):
///   "SHVOLCK1" | u64 identity | i32 width | i32 height | u32 flags | u32 count[w·h] |
///   f64 sum[3·w·h] | (flags bit 0: f64 sumSq[3·w·h]) | u64 FNV-1a checksum of all before it.
/// Files are written atomically (temporary + rename), so a kill during a write leaves the previous
/// checkpoint intact.
#include <cstdint>
#include <string>
#include <vector>

#include "shvol/io/json_reader.h"
#include "shvol/render/film.h"

namespace shvol {

/// Identity of a render for checkpoints: FNV-1a of its scene document (sceneDocument, after the
/// overrides) with render.spp removed (a checkpoint may be continued to more samples), of
/// `files`, the contents of the files it names (namedFileContents: grids, skies, tables), and of
/// `build`, the shvol that renders (its git revision). Everything else — camera, media, seed,
/// render settings, input files, program — must match: a resumed render is then an
/// uninterrupted one, bit for bit.
uint64_t renderIdentity(Json sceneDoc, const std::string& files, const std::string& build);

void writeCheckpoint(const std::string& path, const Film& film, uint64_t identity);

/// Reads a checkpoint; errors (missing, truncated, corrupt, or written for another render) are
/// one line naming the file.
Film readCheckpoint(const std::string& path, uint64_t identity);

}  // namespace shvol
