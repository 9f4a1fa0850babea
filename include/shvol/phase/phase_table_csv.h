#pragma once
/// \file Reads a tabulated phase function from a CSV file.
///
/// Format: one "angle, value" row per line, angle in degrees (the scattering angle θ between the
/// propagation directions, 0 = forward), value ≥ 0 in any units (it is normalised). Blank lines
/// and lines starting with '#' are ignored; the first remaining line may be a header (it is one
/// if its first cell is not a number). At least 2 rows; angles strictly increasing in [0, 180];
/// see TabulatedPhase for interpolation, extension to 0°/180° and normalisation.
#include <string>

#include "shvol/phase/tabulated_phase.h"

namespace shvol {

/// Every problem is a shvol::Error of the form "FILE: line N: message" (the missing-file error
/// is "FILE: cannot open phase table"; table-wide problems name the last line).
TabulatedPhase readPhaseTableCsv(const std::string& path);

}  // namespace shvol
