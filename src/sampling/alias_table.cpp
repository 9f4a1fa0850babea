#include "shvol/sampling/alias_table.h"

#include <cmath>

#include "shvol/core/error.h"

namespace shvol {

std::vector<AliasColumn> buildAliasTable(const double* weights, int n) {
    if (n <= 0) fail("", "alias table", "needs at least one bin");
    std::vector<double> p(n);
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        p[i] = weights[i] > 0 && std::isfinite(weights[i]) ? weights[i] : 0.0;
        sum += p[i];
    }
    std::vector<AliasColumn> table(n);
    for (int i = 0; i < n; ++i) table[i].alias = i;
    if (!(sum > 0)) return table;  // uniform
    // Scaled so that the mean is 1; columns below it are filled from columns above it.
    int heaviest = 0;
    for (int i = 0; i < n; ++i) {
        p[i] *= n / sum;
        if (p[i] > p[heaviest]) heaviest = i;
    }
    std::vector<int> small, large;
    for (int i = 0; i < n; ++i) (p[i] < 1 ? small : large).push_back(i);
    while (!small.empty() && !large.empty()) {
        const int s = small.back(), l = large.back();
        small.pop_back();
        table[s] = {p[s], l};
        p[l] = (p[l] + p[s]) - 1;  // (Vose's order of operations, which loses the least)
        if (p[l] < 1) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // What is left has p ≈ 1 up to rounding: it keeps its own bin, unless it has no weight.
    for (int i : large) table[i] = {1.0, i};
    for (int i : small)
        table[i] = weights[i] > 0 ? AliasColumn{1.0, i} : AliasColumn{0.0, heaviest};
    return table;
}

std::vector<double> aliasTableProbabilities(const std::vector<AliasColumn>& table) {
    const double n = double(table.size());
    std::vector<double> P(table.size(), 0.0);
    for (size_t j = 0; j < table.size(); ++j) {
        P[j] += table[j].q / n;
        P[size_t(table[j].alias)] += (1 - table[j].q) / n;
    }
    return P;
}

}  // namespace shvol
