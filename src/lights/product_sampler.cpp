#include "shvol/lights/product_sampler.h"

#include <cmath>

#include "shvol/core/error.h"
#include "shvol/sampling/sh_cell_mass.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_integrals.h"

namespace shvol {

int ProductSampler::defaultProductDepth(int order) {
    return std::clamp(int(std::ceil(std::log2(double(std::max(order, 1))))) + 3, 3, 9);
}

ProductSampler::ProductSampler(const SkyHierarchy& sky, int order, int productDepth)
    : sky_(sky), n_(order) {
    if (order < 1 || order > kMaxOrder)
        throw Error("product sampling: order must be in [1, " + std::to_string(kMaxOrder) + "]");
    productDepth_ = productDepth < 0 ? defaultProductDepth(order) : productDepth;
    if (productDepth_ > 12) throw Error("product sampling: product depth must be <= 12");
    depth_ = std::max(productDepth_, sky.levels());
    J_.resize(productDepth_ + 1);
    C_.resize(productDepth_ + 1);
    S_.resize(productDepth_ + 1);
    const int tri = sh::triSize(n_);
    for (int d = 1; d <= productDepth_; ++d) {
        const int cells = 1 << d;
        J_[d].resize(size_t(cells) * tri);
        C_[d].resize(size_t(cells) * n_);
        S_[d].resize(size_t(cells) * n_);
        for (int i = 0; i < cells; ++i) {
            sh::legendreIntegrals(n_, -1 + 2.0 * i / cells, -1 + 2.0 * (i + 1) / cells,
                                  &J_[d][size_t(i) * tri]);
            sh::phiIntegrals(n_, TwoPi * i / cells, TwoPi * (i + 1) / cells, &C_[d][size_t(i) * n_],
                             &S_[d][size_t(i) * n_]);
        }
    }
}

void ProductSampler::rotateZonal(const double* p, const Vec3& axis, double* c) const {
    sh::shEval(n_, axis, c);
    for (int l = 0; l < n_; ++l) {
        const double k = std::sqrt(FourPi / (2 * l + 1)) * p[l];
        for (int m = -l; m <= l; ++m) c[sh::shIndex(l, m)] *= k;
    }
}

void ProductSampler::skyChildren(int level, uint64_t skyNode, double skyAvg, double s[4]) const {
    if (level < sky_.levels()) {
        sky_.childAverages(level, skyNode, skyAvg, s);
    } else {
        s[0] = s[1] = s[2] = s[3] = skyAvg;
    }
}

namespace {
/// Lobe masses of the four children of node (level, iz, iφ) into m.
void lobeMasses(int n, const double* c, const std::vector<double>& J, const std::vector<double>& C,
                const std::vector<double>& S, uint32_t iz, uint32_t iphi, double m[4]) {
    double A[ProductSampler::kMaxOrder], B[ProductSampler::kMaxOrder];
    const int tri = sh::triSize(n);
    for (int r = 0; r < 2; ++r) {
        weightByCoefficients(n, c, &J[size_t(2 * iz + r) * tri], A, B);
        for (int k = 0; k < 2; ++k) {
            const size_t j = size_t(2 * iphi + k) * n;
            m[2 * r + k] = cellMass(n, A, B, &C[j], &S[j]);
        }
    }
}
}  // namespace

void ProductSampler::childWeights(const double* c, const WarpNode& node, double skyAvg,
                                  double w[4]) const {
    const int d = node.level;
    const int sd = std::min(d, sky_.levels());
    skyChildren(d, mortonIndex(node.iz >> (d - sd), node.iphi >> (d - sd)), skyAvg, w);
    if (d >= productDepth_) return;
    double m[4];
    lobeMasses(n_, c, J_[d + 1], C_[d + 1], S_[d + 1], node.iz, node.iphi, m);
    for (int i = 0; i < 4; ++i) w[i] = m[i] > 0 && w[i] > 0 ? m[i] * w[i] : 0.0;
}

WarpSample ProductSampler::sample(const double* c, Vec2 u) const {
    double skyAvg = sky_.rootAverage(), s[4], w[4], m[4], prob = 1;
    if (!(skyAvg > 0)) return {};
    uint64_t skyNode = 0;
    uint32_t iz = 0, ip = 0;
    for (int d = 0; d < depth_; ++d) {
        skyChildren(d, skyNode, skyAvg, s);
        if (d < productDepth_) {
            lobeMasses(n_, c, J_[d + 1], C_[d + 1], S_[d + 1], iz, ip, m);
            for (int i = 0; i < 4; ++i) w[i] = m[i] > 0 && s[i] > 0 ? m[i] * s[i] : 0.0;
        } else {
            for (int i = 0; i < 4; ++i) w[i] = s[i];
        }
        const detail::Split sp(w);
        if (!(sp.total > 0)) return {};
        const int r = detail::choose(sp.pRow0, u.x());
        const int k = detail::choose(sp.pCol0[r], u.y());
        const int i = 2 * r + k;
        prob *= sp.c[i] / sp.total;
        if (d < sky_.levels()) skyNode = 4 * skyNode + i, skyAvg = s[i];
        iz = 2 * iz + r, ip = 2 * ip + k;
    }
    const double cells = double(1 << depth_), hz = 2 / cells, hp = TwoPi / cells;
    return {-1 + (iz + u.x()) * hz, (ip + u.y()) * hp, prob / (hz * hp)};
}

double ProductSampler::pdf(const double* c, const Vec3& wdir) const {
    double skyAvg = sky_.rootAverage(), s[4], w[4], m[4], prob = 1;
    if (!(skyAvg > 0)) return 0;
    uint32_t izLeaf, ipLeaf;
    skyCell(wdir, depth_, &izLeaf, &ipLeaf);
    uint64_t skyNode = 0;
    uint32_t iz = 0, ip = 0;
    for (int d = 0; d < depth_; ++d) {
        skyChildren(d, skyNode, skyAvg, s);
        if (d < productDepth_) {
            lobeMasses(n_, c, J_[d + 1], C_[d + 1], S_[d + 1], iz, ip, m);
            for (int i = 0; i < 4; ++i) w[i] = m[i] > 0 && s[i] > 0 ? m[i] * s[i] : 0.0;
        } else {
            for (int i = 0; i < 4; ++i) w[i] = s[i];
        }
        const int shift = depth_ - 1 - d;
        const int r = (izLeaf >> shift) & 1, k = (ipLeaf >> shift) & 1, i = 2 * r + k;
        const detail::Split sp(w);
        if (!(sp.c[i] > 0)) return 0;
        prob *= sp.c[i] / sp.total;
        if (d < sky_.levels()) skyNode = 4 * skyNode + i, skyAvg = s[i];
        iz = 2 * iz + r, ip = 2 * ip + k;
    }
    const double cells = double(1 << depth_);
    return prob / ((2 / cells) * (TwoPi / cells));
}

void ProductSampler::sample(const double* c, const std::vector<Vec2>& u,
                            std::vector<WarpSample>& out) const {
    out.resize(u.size());
    hierarchicalWarpPoints(
        [this, c](const WarpNode& nd, double w[4]) {
            const int sd = std::min(nd.level, sky_.levels());
            const int shift = nd.level - sd;
            childWeights(c, nd, sky_.samplingAverage(sd, nd.iz >> shift, nd.iphi >> shift), w);
        },
        depth_, u.data(), int(u.size()), out.data());
}

WarpSample ProductSampler::sample(const double* c, double beta, Vec2 u) const {
    if (beta <= 0) return sample(c, u);
    WarpSample s;
    if (u.x() < beta) {
        s = sky_.sample(Vec2(u.x() / beta, u.y()));
    } else {
        s = sample(c, Vec2((u.x() - beta) / (1 - beta), u.y()));
    }
    // A failed branch yields no sample (its lost mass is what its pdf leaves out).
    if (!(s.pdf > 0)) return {};
    s.pdf = pdf(c, beta, s.direction());
    return s;
}

double ProductSampler::pdf(const double* c, double beta, const Vec3& w) const {
    if (beta <= 0) return pdf(c, w);
    return (1 - beta) * pdf(c, w) + beta * sky_.pdf(w);
}

double ProductSampler::defensiveShare(double lobeMinimum) const {
    return lobeMinimum < 0 || sky_.compressed() ? kDefensiveFraction : 0.0;
}

}  // namespace shvol
