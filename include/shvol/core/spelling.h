#pragma once
/// \file The word a mistyped one was most likely meant to be, for "did you mean" in messages.
#include <string>
#include <vector>

namespace shvol {

/// Edits (insert, delete, substitute, or swap two neighbours) from a to b: the optimal string
/// alignment distance (Damerau's transposition, each substring edited once).
size_t editDistance(const std::string& a, const std::string& b);

/// The word of `known` nearest to `word` within 2 edits and a third of its length (a typo's
/// reach: "camra" → "camera", never "x" → "y"), the first of equals; "" when none is, or when
/// `word` itself is known.
std::string nearestSpelling(const std::string& word, const std::vector<std::string>& known);

}  // namespace shvol
