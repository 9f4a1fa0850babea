#include "shvol/sampling/distribution_2d.h"

#include <algorithm>

#include "shvol/core/error.h"

namespace shvol {

namespace {
std::vector<double> rowIntegrals(const std::vector<Distribution1D>& rows) {
    std::vector<double> m(rows.size());
    for (size_t v = 0; v < rows.size(); ++v) m[v] = rows[v].integral();
    return m;
}
std::vector<Distribution1D> makeRows(const double* f, int nu, int nv) {
    if (nu <= 0 || nv <= 0) fail("", "Distribution2D", "needs at least one bin in each direction");
    std::vector<Distribution1D> rows;
    rows.reserve(nv);
    for (int v = 0; v < nv; ++v) rows.emplace_back(f + size_t(v) * nu, nu);
    return rows;
}
}  // namespace

Distribution2D::Distribution2D(const double* f, int nu, int nv)
    : nu_(nu),
      nv_(nv),
      conditional_(makeRows(f, nu, nv)),
      marginal_(rowIntegrals(conditional_).data(), nv) {}

Vec2 Distribution2D::sampleContinuous(const Vec2& u, double* pdf, Eigen::Vector2i* cell) const {
    double pdfV = 0, pdfU = 0;
    int v = 0, iu = 0;
    const double y = marginal_.sampleContinuous(u[1], &pdfV, &v);
    const double x = conditional_[v].sampleContinuous(u[0], &pdfU, &iu);
    if (pdf) *pdf = pdfU * pdfV;
    if (cell) *cell = {iu, v};
    return {x, y};
}

double Distribution2D::pdf(const Vec2& p) const {
    const int iu = std::clamp(int(p[0] * nu_), 0, nu_ - 1);
    const int iv = std::clamp(int(p[1] * nv_), 0, nv_ - 1);
    if (!(marginal_.integral() > 0)) return 1.0;
    return conditional_[iv].func(iu) / marginal_.integral();
}

}  // namespace shvol
