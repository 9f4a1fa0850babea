#include "shvol/lights/product_sampler.h"

#include <cmath>

#include "shvol/core/error.h"
#include "shvol/sampling/sh_cell_mass.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_integrals.h"

namespace shvol {

int ProductSampler::defaultProductDepth(int order) {
    return std::clamp(int(std::ceil(std::log2(double(std::max(order, 1))))) + 2, 3, 9);
}

ProductSampler::ProductSampler(const SkyHierarchy& sky, int order, int productDepth)
    : sky_(sky), n_(order) {
    if (order < 1 || order > kMaxOrder)
        throw Error("product sampling: order must be in [1, " + std::to_string(kMaxOrder) + "]");
    productDepth_ = productDepth < 0 ? defaultProductDepth(order) : productDepth;
    if (productDepth_ > 12) throw Error("product sampling: product depth must be <= 12");
    depth_ = std::max(productDepth_, sky.levels());
    for (int l = 0; l < n_; ++l) zonalScale_.push_back(std::sqrt(FourPi / (2 * l + 1)));
    J_.resize(productDepth_ + 1);
    C_.resize(productDepth_ + 1);
    S_.resize(productDepth_ + 1);
    const int tri = sh::triSize(n_);
    for (int d = 0; d <= productDepth_; ++d) {
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
        const double k = zonalScale_[l] * p[l];
        for (int m = -l; m <= l; ++m) c[sh::shIndex(l, m)] *= k;
    }
}

int ProductSampler::significantBands(const std::vector<double>& p) {
    int n = 1;
    for (int l = 1; l < int(p.size()); ++l)
        if (std::abs(p[l]) > 1e-9 * std::abs(p[0])) n = l + 1;
    return n;
}

void ProductSampler::rotateZonal(const double* p, const Vec3& axis, ZonalLobe& lobe,
                                 int bands) const {
    const int n = lobe.n = bands > 0 ? std::min(bands, n_) : n_;
    const double s = std::hypot(axis.x(), axis.y());
    sh::legendreNormalized(n, std::clamp(axis.z(), -1.0, 1.0), s, lobe.q);
    for (int l = 0, t = 0; l < n; ++l) {
        const double k = zonalScale_[l] * p[l];
        for (int m = 0; m <= l; ++m, ++t) lobe.q[t] *= k;
    }
    // cos mφ₀, sin mφ₀ by the multiple-angle recurrence (φ₀ = 0 on the axis, as sh_basis.h).
    const double c1 = s > 0 ? axis.x() / s : 1.0, s1 = s > 0 ? axis.y() / s : 0.0;
    lobe.cosm[0] = 1, lobe.sinm[0] = 0;
    for (int m = 1; m < n; ++m) {
        lobe.cosm[m] = lobe.cosm[m - 1] * c1 - lobe.sinm[m - 1] * s1;
        lobe.sinm[m] = lobe.sinm[m - 1] * c1 + lobe.cosm[m - 1] * s1;
    }
}

void ProductSampler::skyChildren(int level, uint64_t skyNode, double skyAvg, double s[4]) const {
    if (level < sky_.levels()) {
        sky_.prefetchGrandchildren(level, skyNode);
        sky_.childAverages(level, skyNode, skyAvg, s);
    } else {
        s[0] = s[1] = s[2] = s[3] = skyAvg;
    }
}

void ProductSampler::lobeMasses(const SHLobe& lobe, int level, uint32_t iz, uint32_t iphi,
                                double m[4]) const {
    double A[kMaxOrder], B[kMaxOrder];
    const int tri = sh::triSize(n_);
    const std::vector<double>&J = J_[level + 1], &C = C_[level + 1], &S = S_[level + 1];
    for (int r = 0; r < 2; ++r) {
        weightByCoefficients(n_, lobe.c, &J[size_t(2 * iz + r) * tri], A, B);
        for (int k = 0; k < 2; ++k) {
            const size_t j = size_t(2 * iphi + k) * n_;
            m[2 * r + k] = cellMass(n_, A, B, &C[j], &S[j]);
        }
    }
}

void ProductSampler::lobeMasses(const ZonalLobe& lobe, int level, uint32_t iz, uint32_t iphi,
                                double m[4]) const {
    // Tables are laid out for n_ bands; the lobe uses the first n (triangular prefixes).
    const int tri = sh::triSize(n_), n = lobe.n;
    const std::vector<double>&J = J_[level + 1], &C = C_[level + 1], &S = S_[level + 1];
    double G[2][kMaxOrder];  // G_0 and 2·G_m, G_m = ∫cos(m(φ − φ₀)) dφ over the φ-children
    for (int k = 0; k < 2; ++k) {
        const double *Ck = &C[size_t(2 * iphi + k) * n_], *Sk = &S[size_t(2 * iphi + k) * n_];
        G[k][0] = Ck[0];
        for (int mm = 1; mm < n; ++mm)
            G[k][mm] = 2 * (lobe.cosm[mm] * Ck[mm] + lobe.sinm[mm] * Sk[mm]);
    }
    for (int r = 0; r < 2; ++r) {
        double Sm[kMaxOrder] = {};
        const double* Jr = &J[size_t(2 * iz + r) * tri];
        for (int l = 0, t = 0; l < n; ++l)
            for (int mm = 0; mm <= l; ++mm, ++t) Sm[mm] += lobe.q[t] * Jr[t];
        for (int k = 0; k < 2; ++k) {
            double sum = 0;
            for (int mm = 0; mm < n; ++mm) sum += Sm[mm] * G[k][mm];
            m[2 * r + k] = sum;
        }
    }
}

/// A general SH lobe has no state to carry: each level's masses come from lobeMasses.
template <>
class ProductSampler::Descent<ProductSampler::SHLobe> {
  public:
    Descent(const ProductSampler& ps, const SHLobe& lobe) : ps_(ps), lobe_(lobe) {}
    void masses(int level, uint32_t iz, uint32_t iphi, double m[4]) {
        ps_.lobeMasses(lobe_, level, iz, iphi, m);
    }
    void follow(int, int) {}

  private:
    const ProductSampler& ps_;
    const SHLobe& lobe_;
};

/// The zonal fast path along one root-to-leaf path. Integrals are additive over intervals, so of
/// the two z-children only the lower one's S_m is computed from the tables (n(n+1)/2 terms) and
/// the upper one's is the parent's minus it; likewise for the two φ-children's G_m. Each level
/// then costs n(n+1)/2 + 2n + 4n instead of n(n+1) + 4n + 4n. sample() and pdf() both walk this
/// way, so they agree to the last bit for a direction inside a leaf (one that rounds onto a leaf
/// boundary may be attributed to the neighbouring leaf by pdf(), with probability ~1e-16).
template <>
class ProductSampler::Descent<ProductSampler::ZonalLobe> {
  public:
    Descent(const ProductSampler& ps, const ZonalLobe& lobe) : ps_(ps), lobe_(lobe), n_(lobe.n) {
        zIntegrals(0, 0, Sp_);  // the root: z ∈ [−1, 1], φ ∈ [0, 2π)
        phiIntegrals(0, 0, Gp_);
    }
    void masses(int level, uint32_t iz, uint32_t iphi, double m[4]) {
        zIntegrals(level + 1, 2 * iz, S_[0]);
        phiIntegrals(level + 1, 2 * iphi, G_[0]);
        for (int mm = 0; mm < n_; ++mm) S_[1][mm] = Sp_[mm] - S_[0][mm];
        for (int mm = 0; mm < n_; ++mm) G_[1][mm] = Gp_[mm] - G_[0][mm];
        for (int r = 0; r < 2; ++r)
            for (int k = 0; k < 2; ++k) {
                double sum = 0;
                for (int mm = 0; mm < n_; ++mm) sum += S_[r][mm] * G_[k][mm];
                m[2 * r + k] = sum;
            }
    }
    /// Moves to child (r, c) of the node whose masses were computed last.
    void follow(int r, int c) {
        std::copy(S_[r], S_[r] + n_, Sp_);
        std::copy(G_[c], G_[c] + n_, Gp_);
    }

  private:
    /// S_m = Σ_l q_l^m J_l^m over z-interval i of level d.
    void zIntegrals(int d, uint32_t i, double* S) const {
        const double* J = &ps_.J_[d][size_t(i) * sh::triSize(ps_.n_)];
        std::fill(S, S + n_, 0.0);
        for (int l = 0, t = 0; l < n_; ++l)
            for (int mm = 0; mm <= l; ++mm, ++t) S[mm] += lobe_.q[t] * J[t];
    }
    /// G_0 and 2·G_m, G_m = ∫cos(m(φ − φ₀)) dφ over φ-interval i of level d.
    void phiIntegrals(int d, uint32_t i, double* G) const {
        const double *C = &ps_.C_[d][size_t(i) * ps_.n_], *S = &ps_.S_[d][size_t(i) * ps_.n_];
        G[0] = C[0];
        for (int mm = 1; mm < n_; ++mm)
            G[mm] = 2 * (lobe_.cosm[mm] * C[mm] + lobe_.sinm[mm] * S[mm]);
    }

    const ProductSampler& ps_;
    const ZonalLobe& lobe_;
    int n_;
    double Sp_[kMaxOrder], Gp_[kMaxOrder], S_[2][kMaxOrder], G_[2][kMaxOrder];
};

template <class Masses>
void ProductSampler::weights(Masses&& masses, int d, const double s[4], double w[4]) const {
    if (d >= productDepth_) {
        for (int i = 0; i < 4; ++i) w[i] = s[i];
        return;
    }
    double m[4];
    masses(m);
    for (int i = 0; i < 4; ++i) w[i] = m[i] > 0 && s[i] > 0 ? m[i] * s[i] : 0.0;
}

template <class Lobe>
void ProductSampler::childWeights(const Lobe& lobe, const WarpNode& node, double skyAvg,
                                  double w[4]) const {
    const int d = node.level;
    const int sd = std::min(d, sky_.levels());
    double s[4];
    skyChildren(d, mortonIndex(node.iz >> (d - sd), node.iphi >> (d - sd)), skyAvg, s);
    weights([&](double m[4]) { lobeMasses(lobe, d, node.iz, node.iphi, m); }, d, s, w);
}

/// The descent that sample() and pdf() share: at each level the children's product weights are
/// formed and choose(level, split) picks a child (or −1 to stop with no density). Returns the
/// product of the chosen split probabilities and the leaf cell (iz, iφ) at level depth().
template <class Lobe, class Choose>
double ProductSampler::descend(const Lobe& lobe, Choose&& choose, uint32_t* izOut,
                               uint32_t* ipOut) const {
    double skyAvg = sky_.samplingRoot(), s[4], w[4], prob = 1;
    if (!(skyAvg > 0)) return 0;
    uint64_t skyNode = 0;
    uint32_t iz = 0, ip = 0;
    Descent<Lobe> lobeWalk(*this, lobe);
    for (int d = 0; d < depth_; ++d) {
        skyChildren(d, skyNode, skyAvg, s);
        weights([&](double m[4]) { lobeWalk.masses(d, iz, ip, m); }, d, s, w);
        const detail::Split sp(w);
        const int i = choose(d, sp);
        if (i < 0) return 0;
        const int r = i >> 1, k = i & 1;
        if (d < productDepth_) lobeWalk.follow(r, k);
        prob *= sp.c[i] / sp.total;
        if (d < sky_.levels()) skyNode = 4 * skyNode + i, skyAvg = s[i];
        iz = 2 * iz + r, ip = 2 * ip + k;
    }
    *izOut = iz, *ipOut = ip;
    return prob;
}

template <class Lobe>
WarpSample ProductSampler::warp(const Lobe& lobe, Vec2 u) const {
    uint32_t iz, ip;
    const double prob = descend(
        lobe,
        [&](int, const detail::Split& sp) {
            if (!(sp.total > 0)) return -1;
            const int r = detail::choose(sp.pRow0, u.x());
            return 2 * r + detail::choose(sp.pCol0[r], u.y());
        },
        &iz, &ip);
    if (!(prob > 0)) return {};
    const double cells = double(1 << depth_), hz = 2 / cells, hp = TwoPi / cells;
    return {-1 + (iz + u.x()) * hz, (ip + u.y()) * hp, prob / (hz * hp)};
}

template <class Lobe>
double ProductSampler::pdf(const Lobe& lobe, const Vec3& wdir) const {
    uint32_t izLeaf, ipLeaf, iz, ip;
    skyCell(wdir, depth_, &izLeaf, &ipLeaf);
    sky_.prefetchPath(izLeaf >> (depth_ - sky_.levels()), ipLeaf >> (depth_ - sky_.levels()));
    const double prob = descend(
        lobe,
        [&](int d, const detail::Split& sp) {
            const int shift = depth_ - 1 - d;
            const int i = 2 * ((izLeaf >> shift) & 1) + ((ipLeaf >> shift) & 1);
            return sp.c[i] > 0 ? i : -1;
        },
        &iz, &ip);
    const double cells = double(1 << depth_);
    return prob / ((2 / cells) * (TwoPi / cells));
}

template <class Lobe>
void ProductSampler::warp(const Lobe& lobe, const std::vector<Vec2>& u,
                          std::vector<WarpSample>& out) const {
    out.resize(u.size());
    hierarchicalWarpPoints(
        [this, &lobe](const WarpNode& nd, double w[4]) {
            const int sd = std::min(nd.level, sky_.levels());
            const int shift = nd.level - sd;
            childWeights(lobe, nd, sky_.samplingAverage(sd, nd.iz >> shift, nd.iphi >> shift), w);
        },
        depth_, u.data(), int(u.size()), out.data());
}

template <class Lobe>
WarpSample ProductSampler::warp(const Lobe& lobe, double beta, Vec2 u) const {
    if (beta <= 0) return warp(lobe, u);
    // The branch that drew the sample knows its own density; only the other one is evaluated.
    // A failed branch yields no sample (its lost mass is what its pdf leaves out); a NaN density
    // goes on, for the path tracer to count (InvalidDraws).
    WarpSample s;
    if (u.x() < beta) {
        s = sky_.warp(Vec2(u.x() / beta, u.y()));
        if (s.pdf <= 0) return {};
        s.pdf = (1 - beta) * pdf(lobe, s.direction()) + beta * s.pdf;
    } else {
        s = warp(lobe, Vec2((u.x() - beta) / (1 - beta), u.y()));
        if (s.pdf <= 0) return {};
        s.pdf = (1 - beta) * s.pdf + beta * sky_.pdf(s.direction());
    }
    return s;
}

template <class Lobe>
double ProductSampler::pdf(const Lobe& lobe, double beta, const Vec3& w) const {
    if (beta <= 0) return pdf(lobe, w);
    return (1 - beta) * pdf(lobe, w) + beta * sky_.pdf(w);
}

double ProductSampler::lobeValue(const SHLobe& lobe, const Vec3& w) const {
    return sh::shReconstruct(n_, lobe.c, w);
}

double ProductSampler::lobeValue(const ZonalLobe& lobe, const Vec3& w) const {
    double P[sh::triSize(kMaxOrder)];
    const double s = std::hypot(w.x(), w.y());
    sh::legendreNormalized(lobe.n, std::clamp(w.z(), -1.0, 1.0), s, P);
    // cos m(φ − φ₀) = cos mφ cos mφ₀ + sin mφ sin mφ₀, cos mφ and sin mφ by the recurrence.
    const double c1 = s > 0 ? w.x() / s : 1.0, s1 = s > 0 ? w.y() / s : 0.0;
    double cosm = 1, sinm = 0, sum = 0;
    for (int m = 0; m < lobe.n; ++m) {
        double band = 0;
        for (int l = m; l < lobe.n; ++l) band += lobe.q[sh::triIndex(l, m)] * P[sh::triIndex(l, m)];
        sum += (m == 0 ? 1.0 : 2 * (cosm * lobe.cosm[m] + sinm * lobe.sinm[m])) * band;
        const double c = cosm * c1 - sinm * s1;
        sinm = sinm * c1 + cosm * s1, cosm = c;
    }
    return sum;
}

template <class Lobe>
SphereSample ProductSampler::sample(const Lobe& lobe, double beta, Vec2 u) const {
    return withValue(warp(lobe, beta, u),
                     [&](const Vec3& w) { return lobeValue(lobe, w) * sky_.value(w); });
}

double ProductSampler::defensiveShare(double lobeMinimum) const {
    return lobeMinimum < 0 || sky_.compressed() ? kDefensiveFraction : 0.0;
}

// Both lobe forms.
#define SHVOL_PRODUCT_LOBE(L)                                                   \
    template WarpSample ProductSampler::warp(const L&, Vec2) const;             \
    template double ProductSampler::pdf(const L&, const Vec3&) const;           \
    template void ProductSampler::warp(const L&, const std::vector<Vec2>&,      \
                                       std::vector<WarpSample>&) const;         \
    template WarpSample ProductSampler::warp(const L&, double, Vec2) const;     \
    template SphereSample ProductSampler::sample(const L&, double, Vec2) const; \
    template double ProductSampler::pdf(const L&, double, const Vec3&) const;   \
    template void ProductSampler::childWeights(const L&, const WarpNode&, double, double[4]) const;
SHVOL_PRODUCT_LOBE(ProductSampler::SHLobe)
SHVOL_PRODUCT_LOBE(ProductSampler::ZonalLobe)
#undef SHVOL_PRODUCT_LOBE

}  // namespace shvol
