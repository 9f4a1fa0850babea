#include "shvol/sampling/alias_table.h"

#include <cmath>

#include "shvol/core/error.h"

namespace shvol {

std::vector<AliasColumn> buildAliasTable(const double* weights, int n) {
    if (n <= 0) fail("", "alias table", "needs at least one bin");
    std::vector<double> w(size_t(n), 0.0);
    int heaviest = 0;
    for (int i = 0; i < n; ++i) {
        if (weights[i] > 0 && std::isfinite(weights[i])) w[size_t(i)] = weights[i];
        if (w[size_t(i)] > w[size_t(heaviest)]) heaviest = i;
    }
    std::vector<AliasColumn> table(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) table[size_t(i)].alias = i;
    const double wMax = w[size_t(heaviest)];
    if (!(wMax > 0)) return table;  // uniform
    // p = n w / Σw, the mean 1, through w / wMax so that neither the sum overflows nor n/Σw does
    // for subnormal weights. Columns below the mean are filled from columns above it.
    double sum = 0;
    for (double& x : w) sum += (x /= wMax);
    std::vector<double> p(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) p[size_t(i)] = w[size_t(i)] / sum * n;
    std::vector<int> small, large;
    for (int i = 0; i < n; ++i) (p[size_t(i)] < 1 ? small : large).push_back(i);
    while (!small.empty() && !large.empty()) {
        const int s = small.back(), l = large.back();
        small.pop_back();
        table[size_t(s)] = {p[size_t(s)], l};
        p[size_t(l)] = (p[size_t(l)] + p[size_t(s)]) - 1;  // (Vose's order: loses the least)
        if (p[size_t(l)] < 1) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // What is left has p ≈ 1 up to rounding: it keeps its own bin, unless it has no weight.
    for (int i : large) table[size_t(i)] = {1.0, i};
    for (int i : small)
        table[size_t(i)] = w[size_t(i)] > 0 ? AliasColumn{1.0, i} : AliasColumn{0.0, heaviest};
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
