#pragma once
/// \file Walker's alias method (Walker 1977, "An Efficient Method for Generating Discrete Random
/// Variables with General Distributions"), built by Vose's algorithm (Vose 1991, "A Linear
/// Algorithm for Generating Random Numbers with a Given Distribution").
///
/// For n bins with weights wᵢ ≥ 0 (not all 0) it finds thresholds qᵢ ∈ [0, 1] and aliases aᵢ such
/// that drawing a column j uniformly and keeping j with probability q_j, else taking a_j, draws
/// bin i with probability
///   P(i) = (qᵢ + Σ_{j : a_j = i} (1 − q_j)) / n = wᵢ / Σw.
/// A draw from one uniform u ∈ [0, 1): j = ⌊u n⌋, r = u n − j; bin j if r < q_j, else a_j, and
/// the position within the bin, du = r/q_j or (r − q_j)/(1 − q_j), is again uniform. It reads
/// one column's (qᵢ, aᵢ), where inverting a CDF searches it.
#include <algorithm>
#include <vector>

#include "shvol/core/math.h"

namespace shvol {

/// One column of an alias table.
struct AliasColumn {
    double q = 1;   ///< the probability of keeping the column's own bin
    int alias = 0;  ///< the bin drawn otherwise; a bin of positive weight
};

/// The alias table of n ≥ 1 weights (negative or NaN weights count as 0). A bin of weight 0 has
/// q = 0, so it is never drawn, and every alias is a bin of positive weight. All weights 0: every
/// column keeps its own bin (the uniform distribution).
std::vector<AliasColumn> buildAliasTable(const double* weights, int n);

/// The probability with which the table draws each bin (the sum above): what it was built
/// to give, up to rounding; for tests.
std::vector<double> aliasTableProbabilities(const std::vector<AliasColumn>& table);

/// The bin a draw u ∈ [0, 1) takes and its position in the bin, du ∈ [0, 1).
struct AliasDraw {
    int bin;
    double du;
};

/// A draw from the table of n columns whose column j is column(j) (an AliasColumn, by value:
/// the caller may store q and the alias in records of its own), u ∈ [0, 1) (clamped into it, NaN
/// to 0, so that r < 1 and a column with q = 1 always keeps its bin).
template <typename Column>
AliasDraw aliasDraw(double u, int n, const Column& column) {
    const double x = clampToUnit(u) * n;
    const int j = std::min(std::max(int(x), 0), n - 1);
    const double r = std::min(std::max(x - j, 0.0), 1.0);
    const AliasColumn c = column(j);
    if (r < c.q) return {j, r / c.q};
    return {c.alias, std::min((r - c.q) / (1 - c.q), 1.0)};
}

}  // namespace shvol
